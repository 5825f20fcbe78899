#pragma once
// Time until two spheres moving in straight lines touch (paper eq. A.1-A.3).
#include <cmath>
#include <limits>

#include "ballagg/collision/crossing.hpp"
#include "ballagg/core/tolerances.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

inline constexpr double kNever = std::numeric_limits<double>::infinity();

// dx = X_i - X_j and dv = V_i - V_j now; sigma = R_i + R_j. Returns the smallest t >= 0
// with |dx + t dv| = sigma while the pair approaches, or kNever: the entry root of
// crossing.hpp in its cancellation-free form. A pair overlapping by round-off (c <= 0)
// that still approaches touches now (t = 0).
template <int D>
double contact_time(const Vec<D>& dx, const Vec<D>& dv, double sigma) {
  const double b = dx.dot(dv);
  if (b >= 0.0) return kNever;
  const double dx2 = dx.squaredNorm();
  const double a = dv.squaredNorm();
  constexpr double k2 = tolerance::kApproach * tolerance::kApproach;
  if (b * b <= k2 * dx2 * a) return kNever;  // tangential up to round-off
  const crossing::Quadratic q{a, b, dx2 - sigma * sigma};
  if (q.c <= 0.0) return 0.0;
  const double disc = crossing::discriminant(q);
  if (disc < 0.0) return kNever;  // the trajectories miss
  return crossing::entry(q, std::sqrt(disc));
}

}  // namespace ballagg
