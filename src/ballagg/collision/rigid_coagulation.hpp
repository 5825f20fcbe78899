#pragma once
// Sticking of two rigid bodies (Richardson 1995 §2.4, eqs. 8-12): the joined body moves
// with the velocity of the common centre of mass, and spins with the angular momentum that
// leaves the total unchanged. Eq. (11) writes the new spin angular momentum as
// b = L_before - M (r x v) about a fixed origin; about the new centre of mass x it is
//   h = h1 + h2 + m1 (x1 - x) x (v1 - v) + m2 (x2 - x) x (v2 - v),
// the same number without the cancellation of large lever arms. The body-frame spin then
// solves I omega = h (12); the engine's free-rotation propagator takes h directly.
#include "ballagg/core/spin.hpp"

namespace ballagg {

template <int D>
struct MomentumState {
  double mass = 0.0;
  Vec<D> centre = Vec<D>::Zero();    // centre of mass (both bodies in one periodic image)
  Vec<D> velocity = Vec<D>::Zero();
  Spin<D> spin_momentum = Spin<D>::Zero();  // h, about the centre of mass
};

template <int D>
MomentumState<D> stuck_together(const MomentumState<D>& a, const MomentumState<D>& b) {
  MomentumState<D> j;
  j.mass = a.mass + b.mass;
  j.centre = (a.mass * a.centre + b.mass * b.centre) / j.mass;
  j.velocity = (a.mass * a.velocity + b.mass * b.velocity) / j.mass;
  j.spin_momentum = a.spin_momentum + b.spin_momentum +
                    a.mass * cross(Vec<D>(a.centre - j.centre), Vec<D>(a.velocity - j.velocity)) +
                    b.mass * cross(Vec<D>(b.centre - j.centre), Vec<D>(b.velocity - j.velocity));
  return j;
}

}  // namespace ballagg
