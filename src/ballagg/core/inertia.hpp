#pragma once
// Mass properties of aggregates of spheres: the inertia tensor of Richardson (1995) eq. (1)
// about the centre of mass, its combination when two aggregates stick (parallel-axis
// theorem), and the principal axes (§2.1.2).
#include <span>

#include <Eigen/Eigenvalues>

#include "ballagg/core/spin.hpp"

namespace ballagg {

template <int D>
struct MassProperties {
  double mass = 0.0;
  Vec<D> centre = Vec<D>::Zero();                             // centre of mass
  InertiaTensor<D> inertia = InertiaTensor<D>::Zero();        // about the centre of mass
};

// Eq. (1): I = sum_i [2/5 m_i R_i^2 1 + m_i (r_i^2 1 - r_i r_i)] with r_i relative to the
// centre of mass (discs: 1/2 m R^2 + m r^2).
template <int D>
MassProperties<D> sphere_mass_properties(std::span<const Vec<D>> centres, std::span<const double> radii,
                                         std::span<const double> masses) {
  MassProperties<D> p;
  for (std::size_t k = 0; k < centres.size(); ++k) {
    p.mass += masses[k];
    p.centre += masses[k] * centres[k];
  }
  p.centre /= p.mass;
  for (std::size_t k = 0; k < centres.size(); ++k) {
    p.inertia += point_inertia(masses[k], Vec<D>(centres[k] - p.centre));
    p.inertia.diagonal().array() += sphere_moment<D>(masses[k], radii[k]);
  }
  return p;
}

// Two bodies given in one frame stuck together: mass, centre and inertia (about the new
// centre) of the whole, by the parallel-axis theorem. O(1) whatever their sizes.
template <int D>
MassProperties<D> combined(const MassProperties<D>& a, const MassProperties<D>& b) {
  MassProperties<D> p;
  p.mass = a.mass + b.mass;
  p.centre = (a.mass * a.centre + b.mass * b.centre) / p.mass;
  p.inertia = a.inertia + point_inertia(a.mass, Vec<D>(a.centre - p.centre)) + b.inertia +
              point_inertia(b.mass, Vec<D>(b.centre - p.centre));
  return p;
}

template <int D>
struct PrincipalAxes {
  Rotation<D> axes = Rotation<D>::Identity();  // columns: principal axes (a proper rotation)
  Spin<D> moments = Spin<D>::Ones();
};

// Diagonalises the (real, symmetric) inertia tensor. In 2D the moment is the tensor itself
// and the axes are those of the frame.
inline PrincipalAxes<3> principal_axes(const InertiaTensor<3>& inertia) {
  Eigen::SelfAdjointEigenSolver<InertiaTensor<3>> solver(inertia);
  PrincipalAxes<3> p;
  p.axes = solver.eigenvectors();
  p.moments = solver.eigenvalues();
  if (p.axes.determinant() < 0.0) p.axes.col(2) *= -1.0;
  return p;
}
inline PrincipalAxes<2> principal_axes(const InertiaTensor<2>& inertia) {
  PrincipalAxes<2> p;
  p.moments[0] = inertia(0, 0);
  return p;
}

}  // namespace ballagg
