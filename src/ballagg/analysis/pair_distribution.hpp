#pragma once
// The pair distribution of Degond et al. 2023 (eq. 4.6), a cumulative count:
//   P(r) = (1/N) sum_{i != j} 1{|X_i - X_j| <= r}
// the mean number of other centres within r of a centre, tabulated on 4R < r < 20R (the
// paper's range: beyond the contacts of N_c, up to ten diameters) at steps of
// kPairDistributionStep R, R the mean radius. Computed for all spheres of the box and,
// in the same pass, for the pairs inside one chosen cluster (normalised by its size).
//
// P(r) is the correlation integral of the centres: for a fractal P(r) ~ r^D_2, so the
// slope of log P against log r over the table is a third estimate of the fractal
// dimension (the correlation dimension, Grassberger & Procaccia 1983), averaged over every
// centre rather than seen from the centre of mass (mass_radius.hpp) or on a fixed grid
// (box_counting.hpp).
//
// The chosen cluster's fit stops at its extent (when that is below 20R): beyond it every
// pair is counted and P is flat, a plateau that would pull D_2 down. A fit of fewer than
// kMinFitPoints distances, or whose slope is outside (0, D + kDimensionExcess], is withheld
// (fit_flaw.hpp).
#include <cstdint>
#include <optional>
#include <vector>

#include "ballagg/analysis/fit_flaw.hpp"
#include "ballagg/analysis/linear_fit.hpp"
#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

inline constexpr double kPairDistributionMin = 4.0;    // first r, in units of R
inline constexpr double kPairDistributionMax = 20.0;   // last r, in units of R
inline constexpr double kPairDistributionStep = 0.25;  // spacing of the table, in units of R

struct PairDistribution {
  std::vector<double> r;        // the table's distances (absolute lengths)
  std::vector<double> all;      // P(r) over every sphere of the box
  std::vector<double> cluster;  // P(r) over the chosen cluster's own pairs
  std::optional<LinearFit> all_fit, cluster_fit;  // log P against log r: slope = D_2 (kept when withheld)
  FitFlaw all_flaw = FitFlaw::none, cluster_flaw = FitFlaw::none;
  // D_2 of each, NaN when withheld.
  double all_dimension = 0.0, cluster_dimension = 0.0;
};

// label: per sphere its cluster; cluster: the chosen one (its spheres have that label);
// cluster_extent: an upper bound on its diameter, where its fit stops.
template <int D>
PairDistribution pair_distribution(const Box<D>& box, const std::vector<Vec<D>>& position, double mean_radius,
                                   const std::vector<std::int32_t>& label, std::int32_t cluster,
                                   double cluster_extent);

extern template PairDistribution pair_distribution<2>(const Box<2>&, const std::vector<Vec<2>>&, double,
                                                      const std::vector<std::int32_t>&, std::int32_t, double);
extern template PairDistribution pair_distribution<3>(const Box<3>&, const std::vector<Vec<3>>&, double,
                                                      const std::vector<std::int32_t>&, std::int32_t, double);

}  // namespace ballagg
