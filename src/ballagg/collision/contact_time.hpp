#pragma once
// Time until two spheres moving in straight lines touch (paper eq. A.1-A.3).
#include <cmath>
#include <limits>

#include "ballagg/collision/crossing.hpp"
#include "ballagg/core/tolerances.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

inline constexpr double kNever = std::numeric_limits<double>::infinity();

// contact_time() past its first test: b = dx.dv < 0, dx2 = |dx|^2.
template <int D>
double approaching_contact_time(double dx2, double b, const Vec<D>& dv, double sigma) {
  const double a = dv.squaredNorm();
  constexpr double k2 = tolerance::kApproach * tolerance::kApproach;
  if (b * b <= k2 * dx2 * a) return kNever;  // tangential up to round-off
  const crossing::Quadratic q{a, b, dx2 - sigma * sigma};
  if (q.c <= 0.0) return 0.0;
  const double disc = crossing::discriminant(q);
  if (disc < 0.0) return kNever;  // the trajectories miss
  return crossing::entry(q, std::sqrt(disc));
}

// dx = X_i - X_j and dv = V_i - V_j now; sigma = R_i + R_j. Returns the smallest t >= 0
// with |dx + t dv| = sigma while the pair approaches, or kNever: the entry root of
// crossing.hpp in its cancellation-free form. A pair overlapping by round-off (c <= 0)
// that still approaches touches now (t = 0).
template <int D>
double contact_time(const Vec<D>& dx, const Vec<D>& dv, double sigma) {
  const double b = dx.dot(dv);
  if (b >= 0.0) return kNever;
  const double dx2 = dx.squaredNorm();
  return approaching_contact_time<D>(dx2, b, dv, sigma);
}

// The same, or kNever for a contact certainly later than `span` from now (span >= 0): for
// a caller that keeps only the earliest of its events and already has one `span` away
// (Smallenburg's EDMD discards contacts the same way). Until the contact,
//     |dx + t dv|^2 - sigma^2 = c + 2 b t + a t^2 >= c + 2 b t   (a >= 0),
// and with b < 0 this bound falls as t grows: c + 2 b span > 0 means the pair is still
// apart at span, and its entry root t* lies beyond it, by at least a t*^2 / (2 |b|) (half
// of t* itself for a grazing pair, whose computed root is the least precise). The test
// asks for a margin of kHorizonMargin of the size of its terms, so that it holds in exact
// arithmetic too; the caller widens span by as much of its times (prediction.hpp), so that
// the root discarded is, rounding included, later than its event, never equal to it.
template <int D>
double contact_time_within(const Vec<D>& dx, const Vec<D>& dv, double sigma, double span) {
  const double b = dx.dot(dv);
  if (b >= 0.0) return kNever;
  const double dx2 = dx.squaredNorm();
  const double c = dx2 - sigma * sigma;
  const double fall = 2.0 * b * span;  // <= 0
  if (c + fall > tolerance::kHorizonMargin * (std::abs(c) - fall)) return kNever;
  return approaching_contact_time<D>(dx2, b, dv, sigma);
}

}  // namespace ballagg
