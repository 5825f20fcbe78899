#pragma once
// Walls as the time-stepping engine applies them (paper §3.1, step (ii)): after a free
// flight, a cluster that crossed a wall is mirrored back into the box as a whole and its
// velocity component reversed (rule 2.2 applied at the end of the step instead of at the
// exact instant).
#include <algorithm>

#include "ballagg/core/state.hpp"

namespace ballagg {

// What keep_inside_walls does to cluster c at time t, without doing it: the rigid shift
// that brings it back inside [0, L] and its velocity afterwards. Also used to show the
// free flight between two steps in trajectory frames (io/frame.hpp).
template <int D>
struct WallCorrection {
  Vec<D> shift = Vec<D>::Zero();
  Vec<D> velocity = Vec<D>::Zero();
  bool reversed = false;  // a velocity component was reversed
};

template <int D>
WallCorrection<D> wall_correction(const State<D>& s, int c, double t, bool reflect = true) {
  const Cluster<D>& k = s.clusters[c];
  WallCorrection<D> w;
  w.velocity = k.velocity;
  if (s.box.periodic()) return w;
  const Vec<D> origin = s.origin(c, t);
  const ClusterExtent<D> e = s.extent(c);
  Vec<D>& v = w.velocity;
  for (int a = 0; a < D; ++a) {
    const double lo = origin[a] + e.lo[a], hi = origin[a] + e.hi[a], length = s.box.length;
    double d = 0.0;
    if (lo < 0.0) {
      const bool outwards = reflect && v[a] < 0.0;
      d = outwards ? -2.0 * lo : -lo;
      if (outwards) { v[a] = -v[a]; w.reversed = true; }
    } else if (hi > length) {
      const bool outwards = reflect && v[a] > 0.0;
      d = outwards ? -2.0 * (hi - length) : -(hi - length);
      if (outwards) { v[a] = -v[a]; w.reversed = true; }
    } else {
      continue;
    }
    d = std::min(d, length - hi);  // do not push it through the opposite wall
    d = std::max(d, -lo);          // wider than the box: align with the lower wall
    w.shift[a] = d;
  }
  return w;
}

// Moves cluster c back inside [0, L] along every axis where it pokes out, at time t. With
// `reflect`, a cluster moving outwards is mirrored through the wall and its velocity
// component reversed (free flight); otherwise, or when it moves inwards (the minimisation
// of the previous step pushed it through the wall), it is only shifted back to touch the
// wall. A cluster wider than the box is aligned with the lower wall (it is pinned along
// that axis). Returns true when the velocity changed.
template <int D>
bool keep_inside_walls(State<D>& s, int c, double t, bool reflect = true) {
  if (s.box.periodic()) return false;
  const WallCorrection<D> w = wall_correction(s, c, t, reflect);
  if (w.shift != Vec<D>::Zero()) s.translate(c, w.shift, t);
  if (w.reversed) s.set_velocity_at_wall(c, w.velocity, t);
  return w.reversed;
}

}  // namespace ballagg
