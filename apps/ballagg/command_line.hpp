#pragma once
// The ballagg command line: every command and option registered on one CLI::App, and
// the parse with its one-line errors. Kept apart from main.cpp (which runs the chosen
// command) so that the parser can be fuzzed without running anything
// (tests/fuzz/fuzz_command_line.cpp).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "ballagg/run/simulation.hpp"
#include "analyze_command.hpp"
#include "plot_command.hpp"
#include "render_command.hpp"
#include "sweep_command.hpp"
#include "verify_command.hpp"

namespace ballagg::cli {

// Bad input, and an output file that cannot be written (a full disk, an unwritable
// directory): both are the user's to mend, reported in one line with nothing half-written.
inline constexpr int kBadInput = 2;

struct ConfigArgs {
  std::string file;
  std::vector<std::string> overrides;
};

// Where the parse puts every argument. Not copyable: the App holds pointers into it.
struct CommandLine {
  CommandLine();
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  CLI::App app{"ballagg: ballistic aggregation of hard spheres (2D and 3D)", "ballagg"};

  CLI::App* run = nullptr;
  ConfigArgs run_args;
  RunOptions run_options;
  std::optional<std::uint64_t> seed;
  std::string resume_dir;

  CLI::App* show = nullptr;  // `ballagg config`
  ConfigArgs show_args;

  AnalyzeCommand analyze;
  SweepCommand sweep;
  PlotCommand plot;
  RenderCommand render;
  VerifyCommand verify;
};

// Parses argv into `cl`. Returns the exit status when the program must stop here: 0 after
// --help or --version (printed on stdout), kBadInput after one line on stderr for a bad
// command line; nothing when a command is to be run.
std::optional<int> parse_command_line(CommandLine& cl, int argc, const char* const* argv);

}  // namespace ballagg::cli
