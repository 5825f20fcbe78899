#pragma once
// Walls in the time-stepping engine (paper §3.1, step (ii)): after a free flight, a cluster
// that crossed a wall is mirrored back into the box as a whole and its velocity component
// reversed (rule 2.2 applied at the end of the step instead of at the exact instant).
#include <algorithm>

#include "ballagg/core/state.hpp"

namespace ballagg {

// Moves cluster c back inside [0, L] along every axis where it pokes out, at time t. With
// `reflect`, a cluster moving outwards is mirrored through the wall and its velocity
// component reversed (free flight); otherwise, or when it moves inwards (the minimisation
// of the previous step pushed it through the wall), it is only shifted back to touch the
// wall. A cluster wider than the box is aligned with the lower wall (it is pinned along
// that axis). Returns true when the velocity changed.
template <int D>
bool keep_inside_walls(State<D>& s, int c, double t, bool reflect = true) {
  if (s.box.periodic()) return false;
  const Cluster<D>& k = s.clusters[c];
  const Vec<D> origin = s.origin(c, t);
  Vec<D> shift = Vec<D>::Zero();
  Vec<D> v = k.velocity;
  bool reversed = false;
  for (int a = 0; a < D; ++a) {
    const double lo = origin[a] + k.lo[a], hi = origin[a] + k.hi[a], length = s.box.length;
    double d = 0.0;
    if (lo < 0.0) {
      const bool outwards = reflect && v[a] < 0.0;
      d = outwards ? -2.0 * lo : -lo;
      if (outwards) { v[a] = -v[a]; reversed = true; }
    } else if (hi > length) {
      const bool outwards = reflect && v[a] > 0.0;
      d = outwards ? -2.0 * (hi - length) : -(hi - length);
      if (outwards) { v[a] = -v[a]; reversed = true; }
    } else {
      continue;
    }
    d = std::min(d, length - hi);  // do not push it through the opposite wall
    d = std::max(d, -lo);          // wider than the box: align with the lower wall
    shift[a] = d;
  }
  if (shift != Vec<D>::Zero()) s.translate(c, shift, t);
  if (reversed) s.set_velocity(c, v, t);
  return reversed;
}

}  // namespace ballagg
