#pragma once
// The motion of one cluster (Richardson 1995 §2.1, Figs. 8 and 11b): the velocity of its
// centre of mass, its angular velocity, and its kinetic energy of translation and of
// rotation,
//   E_trans = 1/2 M |V|^2,    E_rot = 1/2 omega . I omega                  (eq. 2)
// with I the inertia tensor (1) about the centre of mass (each sphere 2/5 m R^2 about its
// centre, a disc 1/2 m R^2). The angular velocity is read from the state file's spin
// columns (final.csv of a rigid-body run); without them clusters only translate (the ed
// and ts engines) and it is zero.
#include <span>
#include <vector>

#include "ballagg/core/sphere_table.hpp"
#include "ballagg/core/spin.hpp"

namespace ballagg {

template <int D>
struct ClusterMotion {
  Vec<D> velocity = Vec<D>::Zero();              // of the centre of mass: momentum / mass
  Spin<D> angular_velocity = Spin<D>::Zero();    // space frame (2D: about the normal)
  double translational_energy = 0.0, rotational_energy = 0.0;
  double spin() const { return angular_velocity.norm(); }  // |omega|
};

// One cluster: its members' centres in one piece (cluster_unwrapping.hpp), and their
// velocities, radii, masses and spins from the table.
template <int D>
ClusterMotion<D> cluster_motion(std::span<const std::int32_t> members, const std::vector<Vec<D>>& position,
                                const SphereTable<D>& table);

extern template ClusterMotion<2> cluster_motion<2>(std::span<const std::int32_t>, const std::vector<Vec<2>>&,
                                                   const SphereTable<2>&);
extern template ClusterMotion<3> cluster_motion<3>(std::span<const std::int32_t>, const std::vector<Vec<3>>&,
                                                   const SphereTable<3>&);

}  // namespace ballagg
