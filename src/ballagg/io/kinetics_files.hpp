#pragma once
// The files of `ballagg analyze --kinetics` (docs/analysis.md, "Kinetics"):
//   kinetics.json          the fitted exponents z and theta with their errors, the window,
//                          the mean-field values
//   kinetics_collapse.csv  the scaled size distribution of every analysed frame (with
//                          frames_mass_spectrum.csv from `analyze --frames`)
#include <map>
#include <string>
#include <vector>

#include "ballagg/analysis/kinetics.hpp"

namespace ballagg {

// File name -> content; kinetics_collapse.csv only when `collapse` is not empty.
std::map<std::string, std::string> kinetics_files(const Kinetics& k, int dimension, const std::string& series_file,
                                                  const std::vector<CollapsePoint>& collapse);

}  // namespace ballagg
