#pragma once
// `ballagg verify RUN_DIR`: the independent checks of a finished run (docs/verify.md).
#include <string>

#include <CLI/CLI.hpp>

namespace ballagg::cli {

struct VerifyCommand {
  CLI::App* command = nullptr;
  std::string run_dir;
};

void add_verify_command(CLI::App& app, VerifyCommand& verify);
// Exit status 0 when every check holds, 1 with one line per violation on stdout; bad input
// (not a run directory) throws InputError.
int run_verify_command(const VerifyCommand& verify);

}  // namespace ballagg::cli
