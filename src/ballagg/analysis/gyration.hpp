#pragma once
// The gyration tensor of a set of sphere centres and the shape indicators drawn from it
// (Degond et al. 2023, §4.2): with Y = X - <X> the centres relative to their centroid,
//   G = (1/N) sum_i Y_i Y_i^T                                  (below eq. 4.3)
//   aspect ratio       A_r = lambda_1 / lambda_2               (4.3)
//   orientation        D = v_1 / |v_1|                         (4.4)
// where lambda_1 >= lambda_2 (>= lambda_3) are the eigenvalues and v_1 the leading
// eigenvector. The radius of gyration is R_g = sqrt(trace G). Every centre counts once,
// whatever its mass, as in the paper (where all masses are equal).
#include <array>
#include <vector>

#include "ballagg/core/vec.hpp"

namespace ballagg {

template <int D>
struct GyrationShape {
  Vec<D> centroid = Vec<D>::Zero();
  std::array<double, D> eigenvalues{};  // descending
  // Unit eigenvectors, in the order of the eigenvalues. Their sign is fixed so that the
  // largest component in magnitude is positive (an axis has no direction).
  std::array<Vec<D>, D> axes{};
  double aspect_ratio = 1.0;          // lambda_1 / lambda_2 (4.3); +inf for a line of centres
  double radius_of_gyration = 0.0;    // sqrt(lambda_1 + ... + lambda_D)
  const Vec<D>& orientation() const { return axes[0]; }  // D (4.4)
};

// Needs at least one point. A single point has A_r = 1 and an arbitrary orientation (the
// first coordinate axis); so does any set whose two leading eigenvalues are equal.
template <int D>
GyrationShape<D> gyration_shape(const std::vector<Vec<D>>& points);

extern template GyrationShape<2> gyration_shape<2>(const std::vector<Vec<2>>&);
extern template GyrationShape<3> gyration_shape<3>(const std::vector<Vec<3>>&);

}  // namespace ballagg
