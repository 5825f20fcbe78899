#pragma once
// `ballagg sweep`: a parameter grid times realizations (docs/sweeps.md).
#include <string>

#include <CLI/CLI.hpp>

#include "ballagg/sweep/sweep_runner.hpp"

namespace ballagg::cli {

struct SweepCommand {
  CLI::App* command = nullptr;
  std::string file;
  SweepOptions options;
};

void add_sweep_command(CLI::App& app, SweepCommand& sweep);
// Runs it (throws InputError on bad input); returns the exit status (1 if a run failed).
int run_sweep_command(SweepCommand& sweep);

}  // namespace ballagg::cli
