#pragma once
// The box-counting fractal dimension (Degond et al. 2023, eq. 4.7): N(eps) = a eps^(-D_f),
// N(eps) the number of cells of a Cartesian grid of side eps laid over the box [0, L]^D
// that hold at least one sphere centre, for eps_m = L / 2^m. D_f and the prefactor a are
// the slope and intercept of the least-squares line log N = log a - D_f log eps over the
// levels with kBoxCountingSmallest R <= eps_m <= L / 2 (the paper's range 3R <= eps <=
// L/2, which cuts the two plateaus: one centre per cell below, one cell for all above).
//
// Cost: one sort of the centres' Morton keys at the finest level, then one linear pass per
// level (a coarser cell is a prefix of the key), so O(N log N) for all levels together.
#include <cstdint>
#include <optional>
#include <vector>

#include "ballagg/analysis/linear_fit.hpp"
#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

inline constexpr double kBoxCountingSmallest = 3.0;  // smallest fitted eps, in units of R
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
  // when fewer than two levels are in range.
  double dimension = 0.0, dimension_error = 0.0;
  double prefactor = 0.0, prefactor_error = 0.0;
};

// points: centres in the box (folded when periodic; a round-off outside is clamped).
// length_unit: R (the mean radius), which sets the fitted range.
template <int D>
BoxCounting box_counting(const Box<D>& box, const std::vector<Vec<D>>& points, double length_unit);

extern template BoxCounting box_counting<2>(const Box<2>&, const std::vector<Vec<2>>&, double);
extern template BoxCounting box_counting<3>(const Box<3>&, const std::vector<Vec<3>>&, double);

}  // namespace ballagg
