#pragma once
// The mass spectrum: how many clusters there are of each size (number of spheres), the
// histogram of Richardson 1995, Figs. 3c-d (there with masses in units of one sphere's).
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "ballagg/analysis/cluster_partition.hpp"

namespace ballagg {

struct MassSpectrumBin {
  std::int32_t size = 0;      // spheres per cluster
  std::int64_t clusters = 0;  // clusters of that size
};

// Ascending sizes, only the sizes that occur.
inline std::vector<MassSpectrumBin> mass_spectrum(const ClusterPartition& clusters) {
  std::map<std::int32_t, std::int64_t> count;
  for (int c = 0; c < clusters.n_clusters(); ++c) ++count[clusters.size(c)];
  std::vector<MassSpectrumBin> bins;
  for (const auto& [size, n] : count) bins.push_back({size, n});
  return bins;
}

}  // namespace ballagg
