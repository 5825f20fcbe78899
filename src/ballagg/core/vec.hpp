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

}  // namespace ballagg
