#pragma once
// The pair distribution of Degond et al. 2023 (eq. 4.6), a cumulative count:
//   P(r) = (1/N) sum_{i != j} 1{|X_i - X_j| <= r}
// the mean number of other centres within r of a centre, tabulated on 4R < r < 20R (the
// paper's range: beyond the contacts of N_c, up to ten diameters) at steps of
// kPairDistributionStep R, R the mean radius. Computed for all spheres of the box and,
// in the same pass, for the pairs inside one chosen cluster (normalised by its size).
#include <cstdint>
#include <vector>

#include "ballagg/core/vec.hpp"
#include "ballagg/spatial/box.hpp"

namespace ballagg {

inline constexpr double kPairDistributionMin = 4.0;    // first r, in units of R
inline constexpr double kPairDistributionMax = 20.0;   // last r, in units of R
inline constexpr double kPairDistributionStep = 0.25;  // spacing of the table, in units of R

struct PairDistribution {
  std::vector<double> r;        // the table's distances (absolute lengths)
  std::vector<double> all;      // P(r) over every sphere of the box
  std::vector<double> cluster;  // P(r) over the chosen cluster's own pairs
};

// label: per sphere its cluster; cluster: the chosen one (its spheres have that label).
template <int D>
PairDistribution pair_distribution(const Box<D>& box, const std::vector<Vec<D>>& position, double mean_radius,
                                   const std::vector<std::int32_t>& label, std::int32_t cluster);

extern template PairDistribution pair_distribution<2>(const Box<2>&, const std::vector<Vec<2>>&, double,
                                                      const std::vector<std::int32_t>&, std::int32_t);
extern template PairDistribution pair_distribution<3>(const Box<3>&, const std::vector<Vec<3>>&, double,
                                                      const std::vector<std::int32_t>&, std::int32_t);

}  // namespace ballagg
