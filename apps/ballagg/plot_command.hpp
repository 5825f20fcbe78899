#pragma once
// `ballagg plot`: the figures of sweeps or runs (scripts/ballagg_plot.py, embedded, run by
// Debian's /usr/bin/python3 with matplotlib; BALLAGG_PYTHON names another interpreter,
// --script another script).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace ballagg::cli {

struct PlotCommand {
  CLI::App* command = nullptr;
  std::vector<std::string> dirs;
  std::string out_dir, format, dpi, size, style, script;
  bool print_script = false;
};

void add_plot_command(CLI::App& app, PlotCommand& plot);
// Returns the script's exit status (2 for bad input, with its one line on stderr).
int run_plot_command(const PlotCommand& plot);

}  // namespace ballagg::cli
