#include "ballagg/analysis/gyration.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

namespace ballagg {
namespace {
// Two leading eigenvalues closer than this fraction of trace G are equal (round-off of a
// set with a symmetry axis of order >= 3): A_r = 1 exactly.
constexpr double kEqualEigenvalues = 1e-12;
}  // namespace

template <int D>
GyrationShape<D> gyration_shape(const std::vector<Vec<D>>& points) {
  using Matrix = Eigen::Matrix<double, D, D>;
  GyrationShape<D> shape;
  const double n = static_cast<double>(points.size());
  for (const Vec<D>& p : points) shape.centroid += p;
  shape.centroid /= n;
  Matrix g = Matrix::Zero();
  for (const Vec<D>& p : points) {
    const Vec<D> y = p - shape.centroid;
    g.noalias() += y * y.transpose();
  }
  g /= n;
  // Symmetric: real eigenvalues in ascending order, orthonormal eigenvectors.
  const Eigen::SelfAdjointEigenSolver<Matrix> solver(g);
  for (int k = 0; k < D; ++k) {
    const int from = D - 1 - k;
    // Round-off can leave a tiny negative eigenvalue for a degenerate set.
    shape.eigenvalues[k] = std::max(solver.eigenvalues()[from], 0.0);
    Vec<D> v = solver.eigenvectors().col(from);
    int largest = 0;
    for (int a = 1; a < D; ++a)
      if (std::abs(v[a]) > std::abs(v[largest])) largest = a;
    if (v[largest] < 0.0) v = -v;
    shape.axes[k] = v;
  }
  double trace = 0.0;
  for (double l : shape.eigenvalues) trace += l;
  shape.radius_of_gyration = std::sqrt(trace);
  const double l1 = shape.eigenvalues[0], l2 = shape.eigenvalues[1];
  if (l1 - l2 <= kEqualEigenvalues * trace || trace == 0.0) {
    shape.aspect_ratio = 1.0;
    if (trace == 0.0) shape.axes[0] = Vec<D>::Unit(0);
  } else {
    shape.aspect_ratio = l2 > 0.0 ? l1 / l2 : std::numeric_limits<double>::infinity();
  }
  return shape;
}

template GyrationShape<2> gyration_shape<2>(const std::vector<Vec<2>>&);
template GyrationShape<3> gyration_shape<3>(const std::vector<Vec<3>>&);

}  // namespace ballagg
