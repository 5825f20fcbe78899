#pragma once
// Fixed-size vectors of the simulation. Dimension D is a compile-time parameter
// (2: discs in a square, 3: spheres in a cube); Eigen gives us tested arithmetic
// and dot products that compile to a handful of instructions.
#include <Eigen/Core>

namespace ballagg {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

}  // namespace ballagg
