#pragma once
// `ballagg analyze RUN_DIR --kinetics [--window T0,T1]`: the kinetic exponents of a run's
// timeseries.csv and, after `analyze --frames`, the scaling collapse of its frames' size
// distributions (analysis/kinetics.hpp, io/kinetics_files.hpp).
#include <optional>
#include <string>
#include <utility>

namespace ballagg {

struct AnalyzeKineticsRequest {
  std::string run_dir;
  std::string out_dir;  // default: RUN_DIR
  std::optional<std::pair<double, double>> window;
};

// Throws InputError (one line) before writing anything. Returns the directory written to.
std::string analyze_kinetics(const AnalyzeKineticsRequest& request);

}  // namespace ballagg
