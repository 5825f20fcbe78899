#include "analyze_command.hpp"

#include <fmt/format.h>

#include "end_of_run_report.hpp"

namespace ballagg::cli {

void add_analyze_command(CLI::App& app, AnalyzeCommand& a) {
  a.command = app.add_subcommand(
      "analyze", "Shape, contacts, pair distribution, fractal dimensions and mass spectrum of a run's final state");
  a.command->add_option("run_dir", a.request.run_dir, "Run directory (reads config.toml and final.csv)");
  a.command->add_option("--state", a.request.state_file, "State file to analyse instead of RUN_DIR/final.csv");
  a.command->add_option("--config", a.request.config_file, "Configuration giving the box (default RUN_DIR/config.toml)");
  a.command->add_option("--out", a.request.out_dir, "Where to write analysis.json and the tables (default RUN_DIR)");
  a.command->add_flag("--quiet,-q", a.quiet, "Only the line naming the output directory");
}

int run_analyze_command(const AnalyzeCommand& a) {
  const std::string dir = analyze_run(a.request);
  if (!a.quiet) fmt::print("{}", analysis_headline_of(dir));
  fmt::print("analysis in {}\n", dir);
  return 0;
}

}  // namespace ballagg::cli
