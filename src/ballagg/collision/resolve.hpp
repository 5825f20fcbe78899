#pragma once
// Applying the collision laws to clusters in the shared state.
#include "ballagg/collision/collision_settings.hpp"
#include "ballagg/collision/laws.hpp"
#include "ballagg/core/state.hpp"

namespace ballagg {

// The TC model (collision.tc_time > 0) reads when each cluster last collided: the state
// keeps those times from the start of a run whose law has it, and only then.
template <int D>
void keep_what_the_law_reads(State<D>& s, const CollisionSettings& law) {
  if (law.tc() > 0.0) s.keep_collision_times();
}

// Bounce of the clusters of the touching spheres i and j at time t (rule 2.6 applied to the
// clusters as bodies, the normal joining the two sphere centres).
template <int D>
void bounce_clusters(State<D>& s, int i, int j, double t, const CollisionSettings& law) {
  const int a = s.spheres.cluster[i], b = s.spheres.cluster[j];
  Cluster<D>& ka = s.clusters[a];
  Cluster<D>& kb = s.clusters[b];
  const Vec<D> n = s.box.separation(s.unwrapped_position(i, t), s.unwrapped_position(j, t)).normalized();
  const bool recent = t - s.last_collision_time(a) < law.tc() || t - s.last_collision_time(b) < law.tc();
  Vec<D> va = ka.velocity, vb = kb.velocity;
  bounce_velocities(ka.mass, va, kb.mass, vb, n, recent ? 1.0 : law.restitution);
  s.set_last_collision_time(a, t);
  s.set_last_collision_time(b, t);
  s.set_velocity(a, va, t);
  s.set_velocity(b, vb, t);
}

// Specular reflection of the whole cluster c at a wall normal to `axis` (rule 2.2).
template <int D>
void reflect_cluster(State<D>& s, int c, int axis, double t) {
  s.set_velocity_at_wall(c, reflect_velocity(s.clusters[c].velocity, axis), t);
}

}  // namespace ballagg
