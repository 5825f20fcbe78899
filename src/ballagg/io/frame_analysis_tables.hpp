#pragma once
// The indicators of `ballagg analyze --frames` against time, one row per analysed frame of
// a trajectory (docs/analysis.md, "Indicators over time"):
//   frames.csv                one row per frame: the headline indicators of analysis.json
//   frames_mass_spectrum.csv  the mass spectrum of every frame (time, size, mass, clusters)
//   frames_clusters.csv       size, mass, R_g and R_max of every cluster of at least
//                             kPopulationMinSize spheres in every frame (R_max against N_a
//                             over time)
#include <cstdint>
#include <map>
#include <string>

#include <fmt/format.h>

#include "ballagg/analysis/aggregate_analysis.hpp"

namespace ballagg {

class FrameAnalysisTables {
 public:
  FrameAnalysisTables();

  // The analysis of the frame at `time` (after `step` events or steps).
  template <int D>
  void add(double time, std::int64_t step, const AggregateAnalysis<D>& a);

  int frames() const { return frames_; }
  // File name -> content.
  std::map<std::string, std::string> files() const;

 private:
  fmt::memory_buffer frames_csv_, spectrum_csv_, clusters_csv_;
  int frames_ = 0;
};

extern template void FrameAnalysisTables::add<2>(double, std::int64_t, const AggregateAnalysis<2>&);
extern template void FrameAnalysisTables::add<3>(double, std::int64_t, const AggregateAnalysis<3>&);

}  // namespace ballagg
