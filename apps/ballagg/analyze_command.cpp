#include "analyze_command.hpp"

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

#include "end_of_run_report.hpp"

namespace ballagg::cli {

void add_analyze_command(CLI::App& app, AnalyzeCommand& a) {
  a.command = app.add_subcommand(
      "analyze", "Shape, contacts, pair distribution, fractal dimensions and mass spectrum of a run's final state");
  a.command->add_option("run_dir", a.request.run_dir, "Run directory (reads config.toml and final.csv)");
  a.command->add_option("--state", a.request.state_file, "State file to analyse instead of RUN_DIR/final.csv");
  a.command->add_option("--config", a.request.config_file, "Configuration giving the box (default RUN_DIR/config.toml)");
  a.command->add_option("--out", a.request.out_dir, "Where to write analysis.json and the tables (default RUN_DIR)");
  a.command->add_flag("--frames", a.frames,
                      "Analyse every frame of RUN_DIR/trajectory.h5md instead of the final state: frames.csv, "
                      "frames_mass_spectrum.csv, frames_clusters.csv");
  a.command->add_option("--times", a.frame_times, "With --frames: only the frames nearest these times (comma-separated)")
      ->delimiter(',')
      ->allow_extra_args(false);  // one token: a run directory after the times is not a time
  a.command->add_flag("--kinetics", a.kinetics,
                      "The exponents of n(t) ~ t^-z and E(t) ~ t^-theta from RUN_DIR/timeseries.csv (kinetics.json) and, "
                      "after --frames, the scaling collapse of the size distribution (kinetics_collapse.csv)");
  a.command->add_option("--window", a.window, "With --kinetics: the fit's window T0,T1 instead of the automatic one")
      ->delimiter(',')
      ->expected(2)
      ->allow_extra_args(false);
  a.command->add_flag("--quiet,-q", a.quiet, "Only the line naming the output directory");
}

namespace {

int run_frames(const AnalyzeCommand& a) {
  if (a.request.run_dir.empty() || !a.request.state_file.empty() || !a.request.config_file.empty())
    throw InputError("analyze --frames: give a run directory (its trajectory.h5md is read), without --state or --config");
  int frames = 0;
  const std::string dir = analyze_frames({a.request.run_dir, a.request.out_dir, a.frame_times}, frames);
  fmt::print("frame analysis of {} frame{} in {}\n", frames, frames == 1 ? "" : "s", dir);
  return 0;
}

int run_kinetics(const AnalyzeCommand& a) {
  if (a.request.run_dir.empty() || !a.request.state_file.empty() || !a.request.config_file.empty())
    throw InputError("analyze --kinetics: give a run directory (its timeseries.csv is read), without --state or --config");
  std::optional<std::pair<double, double>> window;
  if (!a.window.empty()) window = std::pair{a.window[0], a.window[1]};
  const std::string dir = analyze_kinetics({a.request.run_dir, a.request.out_dir, window});
  if (!a.quiet) fmt::print("{}", kinetics_headline_of(dir));
  fmt::print("kinetics in {}\n", dir);
  return 0;
}

}  // namespace


int run_analyze_command(const AnalyzeCommand& a) {
  if ((a.frames || !a.frame_times.empty()) && (a.kinetics || !a.window.empty()))
    throw InputError("analyze: --frames and --kinetics are two commands: run --frames first, then --kinetics");
  if (a.frames || !a.frame_times.empty()) return run_frames(a);
  if (a.kinetics || !a.window.empty()) return run_kinetics(a);
  const std::string dir = analyze_run(a.request);
  if (!a.quiet) fmt::print("{}", analysis_headline_of(dir));
  fmt::print("analysis in {}\n", dir);
  return 0;
}

}  // namespace ballagg::cli
