#pragma once
// `ballagg plot`: the figures of a sweep (scripts/plot_sweep.py, run by Debian's
// /usr/bin/python3 with matplotlib; BALLAGG_PYTHON names another interpreter).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace ballagg::cli {

struct PlotCommand {
  CLI::App* command = nullptr;
  std::vector<std::string> sweep_dirs;
  std::string out_dir;
};

void add_plot_command(CLI::App& app, PlotCommand& plot);
// Returns the script's exit status (2 for bad input, with its one line on stderr).
int run_plot_command(const PlotCommand& plot);

}  // namespace ballagg::cli
