#pragma once
// Predictions shared by the event-driven engines. Each is a pure function of the current
// motion of the clusters involved (anchor, anchor time, velocity), never of the moment the
// prediction is made: the fast engine and the naive reference engine therefore compute
// bit-identical event times and follow the same merge sequence.
#include <algorithm>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/core/state.hpp"

namespace ballagg {

// Absolute time at which spheres i and j (of different clusters) touch, or kNever.
template <int D>
double predicted_contact(const State<D>& s, int i, int j) {
  const Cluster<D>& ci = s.cluster_of(i);
  const Cluster<D>& cj = s.cluster_of(j);
  const double t0 = std::max(ci.anchor_time, cj.anchor_time);
  const Vec<D> dx = s.box.separation(s.unwrapped_position(i, t0), s.unwrapped_position(j, t0));
  const double dt = contact_time<D>(dx, ci.velocity - cj.velocity, s.spheres.radius[i] + s.spheres.radius[j]);
  return t0 + dt;
}

struct WallContact {
  double time = kNever;
  int axis = -1;
};

// First time a sphere of cluster c touches a wall it is moving towards (rule 2.2 applies
// to the whole cluster). The cluster's body-frame bounding box gives this in O(D).
template <int D>
WallContact next_wall_contact(const State<D>& s, int c) {
  WallContact w;
  if (s.box.periodic()) return w;
  const Cluster<D>& k = s.clusters[c];
  for (int a = 0; a < D; ++a) {
    const double v = k.velocity[a];
    double gap;
    if (v > 0.0) {
      gap = s.box.length - (k.anchor[a] + k.hi[a]);
    } else if (v < 0.0) {
      gap = k.anchor[a] + k.lo[a];
    } else {
      continue;
    }
    const double t = k.anchor_time + std::max(gap, 0.0) / std::abs(v);
    if (t < w.time) w = {t, a};
  }
  return w;
}

// Spheres i and j touch at time t (within the contact tolerance).
template <int D>
bool touching(const State<D>& s, int i, int j, double t) {
  const double sigma = (s.spheres.radius[i] + s.spheres.radius[j]) * (1.0 + tolerance::kContact);
  return s.box.separation(s.unwrapped_position(i, t), s.unwrapped_position(j, t)).squaredNorm() <= sigma * sigma;
}

}  // namespace ballagg
