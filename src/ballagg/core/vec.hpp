#pragma once
// Fixed-size vectors of the simulation. Dimension D is a compile-time parameter
// (2: discs in a square, 3: spheres in a cube); Eigen gives us tested arithmetic
// and dot products that compile to a handful of instructions.
#include <algorithm>

#include <Eigen/Core>

namespace ballagg {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

// The squared distance from the point p to the segment from a to a + d.
template <int D>
double squared_distance_to_segment(const Vec<D>& p, const Vec<D>& a, const Vec<D>& d) {
  const Vec<D> rel = p - a;
  const double dd = d.squaredNorm();
  const double t = dd > 0.0 ? std::clamp(rel.dot(d) / dd, 0.0, 1.0) : 0.0;
  return (rel - t * d).squaredNorm();
}

// Relative margin of beyond_squared: far above the rounding of a squared distance (a few
// 1e-16), far below any distance that matters.
inline constexpr double kQuickRejectMargin = 1e-9;

// A squared distance above beyond_squared(bound) belongs to a distance above `bound`
// whatever the rounding: a quick test on squared distances that drops such pairs before an
// exact test on distances (with a square root, and radii read from memory) that keeps
// pairs within `bound` at most drops none that the exact test would keep.
inline double beyond_squared(double bound) {
  const double widened = bound * (1.0 + kQuickRejectMargin);
  return widened * widened;
}

}  // namespace ballagg
