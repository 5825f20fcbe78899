#pragma once
// The largest overlap in a state: max over sphere pairs of (R_i + R_j - |X_i - X_j|) /
// (R_i + R_j). Zero for touching spheres, negative when all are apart. O(N) with a grid.
#include <optional>

#include "ballagg/core/state.hpp"
#include "ballagg/spatial/cell_grid.hpp"

namespace ballagg {

// Pairs farther apart than two largest diameters are not examined: returns nullopt when no
// pair is that close (the largest overlap is then below -1 + 2 R_max / sigma_min).
template <int D>
std::optional<double> max_relative_overlap(const State<D>& s) {
  const int n = s.n_spheres();
  CellGrid<D> grid(s.box, 4.0 * s.max_radius(), n);
  std::vector<Vec<D>> x(n);
  for (int i = 0; i < n; ++i) {
    x[i] = s.position(i, s.time);
    grid.insert(i, x[i]);
  }
  std::optional<double> worst;
  const double reach = 4.0 * s.max_radius();
  for (int i = 0; i < n; ++i) {
    grid.for_each_near(x[i], [&](int j, const Vec<D>& xj) {
      if (j <= i) return;
      const double d = s.box.separation(x[i], xj).norm();
      if (d >= reach) return;
      const double sigma = s.spheres.radius[i] + s.spheres.radius[j];
      const double overlap = (sigma - d) / sigma;
      if (!worst || overlap > *worst) worst = overlap;
    });
  }
  return worst;
}

}  // namespace ballagg
