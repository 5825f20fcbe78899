#pragma once
// `ballagg analyze`: the aggregate analysis of a run's final state (docs/analysis.md).
#include <CLI/CLI.hpp>

#include "ballagg/run/analyze_frames.hpp"
#include "ballagg/run/analyze_kinetics.hpp"
#include "ballagg/run/analyze_run.hpp"

namespace ballagg::cli {

struct AnalyzeCommand {
  CLI::App* command = nullptr;
  AnalyzeRequest request;
  bool frames = false;              // the trajectory's frames instead of the final state
  std::vector<double> frame_times;  // the frames nearest these times (implies frames)
  bool kinetics = false;            // the kinetic exponents of the time series
  std::vector<double> window;       // with kinetics: T0,T1 instead of the automatic window
  bool quiet = false;               // no headline indicators
};

void add_analyze_command(CLI::App& app, AnalyzeCommand& analyze);
// Runs it (throws InputError on bad input); returns the exit status.
int run_analyze_command(const AnalyzeCommand& analyze);

}  // namespace ballagg::cli
