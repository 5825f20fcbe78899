// The ballagg command line. Exit status: 0 success, 2 bad input (one line on stderr,
// nothing written), 1 any other failure.
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "ballagg/config/config.hpp"
#include "ballagg/run/simulation.hpp"
#include "ballagg/version.hpp"
#include "analyze_command.hpp"
#include "plot_command.hpp"
#include "render_command.hpp"
#include "sweep_command.hpp"

namespace {

constexpr int kBadInput = 2;

struct ConfigArgs {
  std::string file;
  std::vector<std::string> overrides;
};

void add_config_args(CLI::App& cmd, ConfigArgs& args) {
  cmd.add_option("config", args.file, "TOML configuration file (default: the built-in 2D example)");
  cmd.add_option("--set", args.overrides, "Override one key, e.g. --set system.n=400 (repeatable)")
      ->type_name("SECTION.KEY=VALUE")
      ->allow_extra_args(false);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ballagg: ballistic aggregation of hard spheres (2D and 3D)", "ballagg"};
  app.set_version_flag("--version", std::string("ballagg ") + ballagg::kVersion);
  app.require_subcommand(1);

  ConfigArgs run_args;
  ballagg::RunOptions run_options;
  std::optional<std::uint64_t> seed;
  CLI::App* run = app.add_subcommand("run", "Run a simulation and write its results to a directory");
  add_config_args(*run, run_args);
  run->add_option("--out", run_options.out_dir, "Output directory (default: out/<timestamp>)");
  // The resolved config.toml stores the seed as a TOML integer, so it must fit in int64.
  run->add_option("--seed", seed, "Random seed (overrides initial.seed)")
      ->check(CLI::Range(std::uint64_t{0}, static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())));
  run->add_flag("--quiet,-q", run_options.quiet, "No progress output");

  ConfigArgs show_args;
  CLI::App* show = app.add_subcommand("config", "Print the configuration that a run would use, as TOML");
  add_config_args(*show, show_args);

  ballagg::cli::AnalyzeCommand analyze;
  ballagg::cli::add_analyze_command(app, analyze);
  ballagg::cli::SweepCommand sweep;
  ballagg::cli::add_sweep_command(app, sweep);
  ballagg::cli::PlotCommand plot;
  ballagg::cli::add_plot_command(app, plot);
  ballagg::cli::RenderCommand render;
  ballagg::cli::add_render_command(app, render);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // CLI11 reports "a subcommand is required" for a misspelt command: name it, and list
    // every registered command.
    if (app.get_subcommands().empty() && argc > 1 && argv[1][0] != '-') {
      std::string commands;
      for (const CLI::App* c : std::as_const(app).get_subcommands({}))
        commands += (commands.empty() ? "" : ", ") + c->get_name();
      fmt::print(stderr, "ballagg: error: unknown command '{}' (commands: {}; see ballagg --help)\n", argv[1], commands);
      return kBadInput;
    }
    fmt::print(stderr, "ballagg: error: {} (see ballagg --help)\n", e.what());
    return kBadInput;
  }

  try {
    if (*analyze.command) return ballagg::cli::run_analyze_command(analyze);
    if (*sweep.command) return ballagg::cli::run_sweep_command(sweep);
    if (*plot.command) return ballagg::cli::run_plot_command(plot);
    if (*render.command) return ballagg::cli::run_render_command(render);
    if (*show) {
      const ballagg::Config c = ballagg::load_config(show_args.file, show_args.overrides);
      std::cout << ballagg::to_toml_text(c);
      return 0;
    }
    ballagg::Config c = ballagg::load_config(run_args.file, run_args.overrides);
    if (seed) c.initial.seed = *seed;
    const std::string dir = ballagg::run_simulation(c, run_options);
    fmt::print("results in {}\n", dir);
    return 0;
  } catch (const ballagg::InputError& e) {
    fmt::print(stderr, "ballagg: error: {}\n", e.what());
    return kBadInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "ballagg: failed: {}\n", e.what());
    return 1;
  }
}
