#include "command_line.hpp"

#include <limits>
#include <utility>

#include <fmt/format.h>

#include "ballagg/core/version.hpp"

namespace ballagg::cli {
namespace {

void add_config_args(CLI::App& cmd, ConfigArgs& args) {
  cmd.add_option("config", args.file, "TOML configuration file (default: the built-in 2D example)");
  cmd.add_option("--set", args.overrides, "Override one key, e.g. --set system.n=400 (repeatable)")
      ->type_name("SECTION.KEY=VALUE")
      ->allow_extra_args(false);
}

// No argument of ballagg means anything when empty: an empty path would otherwise be taken
// for one not given (`--resume ""` starting a new run, `--out ""` writing to
// out/<timestamp>), an empty --set is no key. The name of the first option given an
// empty value, in the command chosen.
std::optional<std::string> first_empty_argument(const CLI::App& app) {
  for (const CLI::App* command : app.get_subcommands())
    for (const CLI::Option* option : command->get_options())
      for (const std::string& value : option->results())
        if (value.empty()) return option->get_name();
  return std::nullopt;
}

}  // namespace

CommandLine::CommandLine() {
  app.set_version_flag("--version", std::string("ballagg ") + kVersion);
  app.require_subcommand(1);

  run = app.add_subcommand("run", "Run a simulation and write its results to a directory");
  add_config_args(*run, run_args);
  run->add_option("--out", run_options.out_dir, "Output directory (default: out/<timestamp>)");
  // The resolved config.toml stores the seed as a TOML integer, so it must fit in int64.
  run->add_option("--seed", seed, "Random seed (overrides initial.seed)")
      ->check(CLI::Range(std::uint64_t{0}, static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())));
  run->add_flag("--quiet,-q", run_options.quiet, "No progress output");
  run->add_flag("--overwrite", run_options.overwrite,
                "Replace the run in --out (its files are removed first; other files stay)");
  CLI::Option* resume = run->add_option("--resume", resume_dir, "Continue the interrupted run in RUN_DIR from its checkpoint")
                            ->type_name("RUN_DIR");
  for (const char* other : {"config", "--set", "--seed", "--out", "--overwrite"}) resume->excludes(run->get_option(other));

  show = app.add_subcommand(
      "config", "Print the configuration a run of these arguments resolves at its start (its config.toml), as TOML");
  add_config_args(*show, show_args);

  add_analyze_command(app, analyze);
  add_sweep_command(app, sweep);
  add_plot_command(app, plot);
  add_render_command(app, render);
  add_verify_command(app, verify);
}

std::optional<int> parse_command_line(CommandLine& cl, int argc, const char* const* argv) {
  CLI::App& app = cl.app;
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
  if (const std::optional<std::string> option = first_empty_argument(app)) {
    fmt::print(stderr, "ballagg: error: {}: an empty argument is not allowed (see ballagg --help)\n", *option);
    return kBadInput;
  }
  return std::nullopt;
}

}  // namespace ballagg::cli
