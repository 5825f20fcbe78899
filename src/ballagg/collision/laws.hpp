#pragma once
// Collision laws between two bodies (clusters that translate without rotating) and with a
// wall. Shared by every engine. Sticking (rule 2.9) is in core/stick_velocity.hpp.
#include "ballagg/core/stick_velocity.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

// Restitution (rules 2.3-2.7): the normal relative velocity g = (v1 - v2).n becomes
// -restitution * g, momentum is conserved and tangential velocities are unchanged;
// n is the unit vector from the centre of body 2's contact sphere to body 1's.
//
// Note on the paper's text: (2.6)-(2.7) read V1' = V1 - 2 alpha (1 - beta) g n with
// alpha = m1 / (m1 + m2), which conserves momentum only for equal masses. Requiring
// m1 V1' + m2 V2' = m1 V1 + m2 V2 gives alpha = m2 / (m1 + m2) for body 1 (and 1 - alpha
// for body 2); with 2 (1 - beta) = 1 + restitution this is the impulse below.
// Does nothing to a pair that is not approaching (g >= 0).
template <int D>
void bounce_velocities(double m1, Vec<D>& v1, double m2, Vec<D>& v2, const Vec<D>& n,
                       double restitution) {
  const double g = (v1 - v2).dot(n);
  if (g >= 0.0) return;
  const double impulse = (1.0 + restitution) * g * (m1 * m2 / (m1 + m2));
  v1 -= (impulse / m1) * n;
  v2 += (impulse / m2) * n;
}

// Specular reflection at a wall normal to axis a (rule 2.2).
template <int D>
Vec<D> reflect_velocity(Vec<D> v, int axis) {
  v[axis] = -v[axis];
  return v;
}

}  // namespace ballagg
