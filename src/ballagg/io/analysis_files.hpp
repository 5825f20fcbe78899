#pragma once
// The files of `ballagg analyze` (docs/analysis.md): analysis.json with every scalar, and
// CSV tables for the curves and the clusters, plain numbers with a header line
// (numpy.genfromtxt(path, delimiter=",", names=True) reads them; NaN is written "nan").
#include <map>
#include <string>

#include "ballagg/analysis/aggregate_analysis.hpp"

namespace ballagg {

// File name -> content: analysis.json, clusters.csv, mass_spectrum.csv, box_counting.csv,
// pair_distribution.csv, mass_radius.csv. `state_file` is recorded in analysis.json.
template <int D>
std::map<std::string, std::string> analysis_files(const AggregateAnalysis<D>& a, const std::string& state_file);

extern template std::map<std::string, std::string> analysis_files<2>(const AggregateAnalysis<2>&, const std::string&);
extern template std::map<std::string, std::string> analysis_files<3>(const AggregateAnalysis<3>&, const std::string&);

}  // namespace ballagg
