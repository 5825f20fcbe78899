#pragma once
// The first contact of two rotating bodies (or of a rotating body and a wall), by
// conservative advancement on the exact trajectories (Mirtich 1996, with a second-order
// bound).
//
// For each candidate pair of spheres the gap g(t) = |x_i - x_j| - (R_i + R_j) is known at
// any time (the free-rotation propagator is exact), with its rate g'. Bounds on the
// relative speed of the two sphere centres, v <= |V_A - V_B| + Omega_A r_i + Omega_B r_j,
// and on their relative acceleration, |a| <= (alpha_A + Omega_A^2) r_i + (alpha_B +
// Omega_B^2) r_j (Omega, alpha: bounds on |omega|, |d omega/dt| over the free flight; r:
// distances of the sphere centres from their centres of mass), bound the curvature of the
// gap: |g''| <= v^2 / (R_i + R_j) + |a| while the spheres are apart. So
//   g(t + h) >= g + g' h - c h^2 / 2,
// and no contact can happen before the positive root h of the right-hand side: the safe
// step. Stepping by it never jumps over a contact; near a contact with g' < 0 the steps
// converge quadratically (the error of a step is O(g^2)). The search stops at the first
// time a pair is within kContactGap of touching and approaching: the contact time is
// then known to that fraction of a diameter (Richardson tolerated overlaps of ~1%).
//
// A pair touching but not approaching (it has just bounced) is passed over with the step
// after which it may overlap by at most kContactGap (the root of g + g' h - c h^2 / 2 =
// -kContactGap sigma; a pair already that deep may sink by a tenth of it more, so that
// time moves on).
#include <cmath>
#include <limits>

namespace ballagg {

// Two spheres are "in contact" when their gap is below kContactGap (R_i + R_j).
inline constexpr double kContactGap = 1e-10;
// A search runs at most this many steps before it hands back to the event loop (it
// resumes at the time it reached, so no step is lost).
inline constexpr int kMaxStepsPerSearch = 256;

// What conservative advancement concludes about one pair at one instant.
struct PairStep {
  bool touching = false;  // within the tolerance and approaching: contact now
  double step = std::numeric_limits<double>::infinity();  // no contact before t + step
};

// gap and rate at time t; tolerance: the contact gap (a length); curvature: a bound on
// |g''| from t on.
inline PairStep advancement_step(double gap, double rate, double tolerance, double curvature) {
  constexpr double never = std::numeric_limits<double>::infinity();
  PairStep s;
  if (gap <= tolerance) {
    if (rate < 0.0) {
      s.touching = true;
      s.step = 0.0;
    } else if (curvature > 0.0) {
      const double room = std::max(gap + tolerance, 0.1 * tolerance);
      s.step = (rate + std::sqrt(rate * rate + 2.0 * curvature * room)) / curvature;
    } else {
      s.step = never;
    }
    return s;
  }
  const double disc = std::sqrt(rate * rate + 2.0 * curvature * gap);
  if (rate < 0.0) {
    s.step = 2.0 * gap / (disc - rate);  // the root written without cancellation
  } else {
    s.step = curvature > 0.0 ? (rate + disc) / curvature : never;
  }
  return s;
}

}  // namespace ballagg
