#pragma once
// Angular quantities of rigid bodies in D dimensions. In 3D an angular velocity, angular
// momentum or torque is a 3-vector; in 2D it is perpendicular to the plane, one number,
// stored as a 1-vector so that the formulas read the same in both dimensions. Inertia
// tensors are kSpinDim x kSpinDim: the 3x3 tensor of Richardson (1995) eq. (1) in 3D, a
// single moment in 2D.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ballagg/core/vec.hpp"

namespace ballagg {

template <int D>
inline constexpr int kSpinDim = D == 2 ? 1 : 3;

template <int D>
using Spin = Eigen::Matrix<double, kSpinDim<D>, 1>;
template <int D>
using InertiaTensor = Eigen::Matrix<double, kSpinDim<D>, kSpinDim<D>>;
// A rotation of D-dimensional space (space <- body): columns are the body axes.
template <int D>
using Rotation = Eigen::Matrix<double, D, D>;

// a x b. In 3D the same function gives w x r, the velocity of a point at r in a body
// spinning at w (Spin<3> and Vec<3> are one type).
inline Vec<3> cross(const Vec<3>& a, const Vec<3>& b) { return a.cross(b); }
inline Spin<2> cross(const Vec<2>& a, const Vec<2>& b) { return Spin<2>(a[0] * b[1] - a[1] * b[0]); }
// w x r in 2D: the velocity of a point at r in a body spinning at w about the normal.
inline Vec<2> cross(const Spin<2>& w, const Vec<2>& r) { return Vec<2>(-w[0] * r[1], w[0] * r[0]); }

// The rotation by angle theta in the plane.
inline Rotation<2> plane_rotation(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Rotation<2> r;
  r << c, -s, s, c;
  return r;
}

// Moment of inertia of a uniform sphere (ball) of mass m and radius r about any diameter:
// 2/5 m r^2 in 3D (eq. 1); a uniform disc about its centre: 1/2 m r^2 in 2D.
template <int D>
double sphere_moment(double m, double r) {
  return (D == 2 ? 0.5 : 0.4) * m * r * r;
}

// The inertia tensor of a point mass m at r about the origin: m (|r|^2 1 - r r^T) in 3D
// (the parallel-axis term of eq. 1), m |r|^2 in 2D.
inline InertiaTensor<3> point_inertia(double m, const Vec<3>& r) {
  return m * (r.squaredNorm() * InertiaTensor<3>::Identity() - r * r.transpose());
}
inline InertiaTensor<2> point_inertia(double m, const Vec<2>& r) { return InertiaTensor<2>(m * r.squaredNorm()); }

// A rotation tensor R I R^T (an inertia tensor expressed in another frame). In 2D inertia
// is a scalar and does not change.
inline InertiaTensor<3> rotate_tensor(const Rotation<3>& r, const InertiaTensor<3>& i) { return r * i * r.transpose(); }
inline InertiaTensor<2> rotate_tensor(const Rotation<2>&, const InertiaTensor<2>& i) { return i; }
// A spin vector in another frame: R w in 3D; unchanged in 2D (rotations keep the normal).
inline Spin<3> rotate_spin(const Rotation<3>& r, const Spin<3>& w) { return r * w; }
inline Spin<2> rotate_spin(const Rotation<2>&, const Spin<2>& w) { return w; }

}  // namespace ballagg
