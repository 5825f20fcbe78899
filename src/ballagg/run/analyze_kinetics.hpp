#pragma once
// `ballagg analyze RUN_DIR --kinetics [--window T0,T1]`: the kinetic exponents of a run's
// timeseries.csv and, after `analyze --frames`, the scaling collapse of its frames' size
// distributions (analysis/kinetics.hpp, io/kinetics_files.hpp).
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "ballagg/run/run_directory.hpp"

namespace ballagg {

struct AnalyzeKineticsRequest {
  std::string run_dir;
  std::string out_dir;  // default: RUN_DIR
  std::optional<std::pair<double, double>> window;
};

// The files of `analyze --kinetics` for a run (file name -> content), nothing written; the
// Python module's Run.kinetics. Throws InputError (one line) for a bad window or table.
std::map<std::string, std::string> kinetics_of_run(const RunDirectory& run,
                                                   std::optional<std::pair<double, double>> window);

// Throws InputError (one line) before writing anything. Returns the directory written to.
std::string analyze_kinetics(const AnalyzeKineticsRequest& request);

}  // namespace ballagg
