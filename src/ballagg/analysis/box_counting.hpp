#pragma once
// The box-counting fractal dimension (Degond et al. 2023, eq. 4.7): N(eps) = a eps^(-D_f),
// N(eps) the number of cells of a Cartesian grid of side eps laid over the box [0, L]^D
// that hold at least one sphere centre, for eps_m = L / 2^m. D_f and the prefactor a are
// the slope and intercept of the least-squares line log N = log a - D_f log eps over the
// levels with kBoxCountingSmallest R <= eps_m <= L / 2 (the paper's range 3R <= eps <=
// L/2, which cuts the two plateaus: one centre per cell below, one cell for all above).
// For one cluster, the upper end is the level nearest to half the cluster's extent E (the
// largest side of its bounding box), as L/2 is half the box's: eps_m <= min(L/2,
// E / sqrt(2)). Above it the cluster sits in one to 2^D cells whatever its shape, a plateau
// that would pull D_f down (a 60 x 60 square in a box of 120 covers 4 cells at both eps = 60
// and 30). A cluster that spans the box keeps the paper's range.
// A fit of fewer than kMinFitPoints levels is withheld (NaN, FitFlaw::too_few_points).
//
// Cost: one sort of the centres' Morton keys at the finest level, then one linear pass per
// level (a coarser cell is a prefix of the key), so O(N log N) for all levels together.
#include <cstdint>
#include <optional>
#include <vector>

#include "ballagg/analysis/fit_flaw.hpp"
#include "ballagg/analysis/linear_fit.hpp"
#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

inline constexpr double kBoxCountingSmallest = 3.0;  // smallest fitted eps, in units of R
// A cluster's coarsest fitted eps, as a fraction of its extent: 1/sqrt(2), half the extent
// rounded (on the log scale of the levels, which halve) to the nearest level.
inline constexpr double kBoxCountingCoarsestOfExtent = 0.70710678118654752;
// The table goes on to finer levels (outside the fit, to show the plateau) while
// eps >= kBoxCountingFinest R.
inline constexpr double kBoxCountingFinest = 0.5;

struct BoxCounting {
  std::vector<int> level;            // m
  std::vector<double> eps;           // L / 2^m
  std::vector<std::int64_t> boxes;   // N(eps_m)
  std::vector<char> fitted;          // eps_m within the fitted range
  std::optional<LinearFit> fit;      // log N against log eps: slope = -D_f, intercept = log a
  // D_f and a with their standard errors (a's by the delta method: a * se(log a)); NaN
  // when the fit is withheld.
  double dimension = 0.0, dimension_error = 0.0;
  double prefactor = 0.0, prefactor_error = 0.0;
  FitFlaw flaw = FitFlaw::none;
};

// points: centres in the box (folded when periodic; a round-off outside is clamped).
// length_unit: R (the mean radius), which sets the fitted range's lower end; largest_eps:
// its upper end (L/2 for the whole box, the paper's; a cluster's diameter if smaller).
template <int D>
BoxCounting box_counting(const Box<D>& box, const std::vector<Vec<D>>& points, double length_unit,
                         double largest_eps);

template <int D>
BoxCounting box_counting(const Box<D>& box, const std::vector<Vec<D>>& points, double length_unit) {
  return box_counting(box, points, length_unit, 0.5 * box.length);
}

extern template BoxCounting box_counting<2>(const Box<2>&, const std::vector<Vec<2>>&, double, double);
extern template BoxCounting box_counting<3>(const Box<3>&, const std::vector<Vec<3>>&, double, double);

}  // namespace ballagg
