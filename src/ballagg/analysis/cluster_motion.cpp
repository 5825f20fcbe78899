#include "ballagg/analysis/cluster_motion.hpp"

#include "ballagg/core/inertia.hpp"

namespace ballagg {

template <int D>
ClusterMotion<D> cluster_motion(std::span<const std::int32_t> members, const std::vector<Vec<D>>& position,
                                const SphereTable<D>& t) {
  ClusterMotion<D> out;
  double mass = 0.0;
  Vec<D> momentum = Vec<D>::Zero();
  for (int i : members) {
    mass += t.mass[i];
    momentum += t.mass[i] * t.velocity[i];
  }
  out.velocity = momentum / mass;
  out.translational_energy = 0.5 * mass * out.velocity.squaredNorm();
  if (t.spin.empty()) return out;
  // Every sphere of a cluster carries the cluster's spin (state_csv.hpp).
  out.angular_velocity = t.spin[members.front()];
  std::vector<Vec<D>> x;
  std::vector<double> radius, masses;
  x.reserve(members.size());
  radius.reserve(members.size());
  masses.reserve(members.size());
  for (int i : members) {
    x.push_back(position[i]);
    radius.push_back(t.radius[i]);
    masses.push_back(t.mass[i]);
  }
  const MassProperties<D> p = sphere_mass_properties<D>(x, radius, masses);
  out.rotational_energy = 0.5 * out.angular_velocity.dot(p.inertia * out.angular_velocity);
  return out;
}

template ClusterMotion<2> cluster_motion<2>(std::span<const std::int32_t>, const std::vector<Vec<2>>&,
                                            const SphereTable<2>&);
template ClusterMotion<3> cluster_motion<3>(std::span<const std::int32_t>, const std::vector<Vec<3>>&,
                                            const SphereTable<3>&);

}  // namespace ballagg
