#pragma once
// When a point moving in a straight line crosses a sphere: the instants t with
// |d + t v| = r, d the point's place now relative to the centre, v its velocity.
//
// Squaring gives (paper eq. A.1-A.2) the quadratic
//     a t^2 + 2 b t + c = 0,   a = |v|^2,  b = d.v,  c = |d|^2 - r^2,
// with the discriminant disc = b^2 - a c; its roots (A.3) are t = (-b -+ sqrt(disc)) / a,
// the entry (the smaller) and the exit (the larger). Written so, the root on the side of
// b's sign subtracts two nearly equal numbers when |a c| << b^2 (a point near the
// surface, or moving nearly along it). Its product with the other root
// is c / a, so it is also c / (-b -+ sqrt(disc)), a sum of terms of one sign: the
// cancellation-free form, used below for each root on that side.
//
// The functions take a, b, c (and sqrt(disc)) rather than d, v and r: a caller often
// decides from b alone that there is no crossing to look for, and computes the rest only
// when there is.
#include <cmath>

#include "ballagg/core/vec.hpp"

namespace ballagg::crossing {

// The coefficients a, b, c of |d + t v|^2 - r^2 = a t^2 + 2 b t + c (A.1-A.2).
struct Quadratic {
  double a, b, c;
};

template <int D>
Quadratic quadratic(const Vec<D>& d, const Vec<D>& v, double r) {
  return {v.squaredNorm(), d.dot(v), d.squaredNorm() - r * r};
}

// b^2 - a c: negative when the line misses the sphere (A.2).
inline double discriminant(const Quadratic& q) { return q.b * q.b - q.a * q.c; }

// The entry, (-b - sqrt(disc)) / a (A.3); root_disc = sqrt(discriminant(q)) >= 0, a > 0.
// For b < 0 (approaching) the cancellation-free c / (-b + sqrt(disc)), which is also
// exact at a = 0 when c is not 0.
inline double entry(const Quadratic& q, double root_disc) {
  return q.b < 0.0 ? q.c / (-q.b + root_disc) : -(q.b + root_disc) / q.a;
}

// The exit, (-b + sqrt(disc)) / a (A.3); root_disc = sqrt(discriminant(q)) >= 0, a > 0.
// For b > 0 (receding) the cancellation-free -c / (b + sqrt(disc)).
inline double exit(const Quadratic& q, double root_disc) {
  return q.b <= 0.0 ? (root_disc - q.b) / q.a : -q.c / (q.b + root_disc);
}

// Both roots as (A.3) writes them, (-b - sqrt(disc)) / a and (-b + sqrt(disc)) / a: for a
// caller that wants the interval between them. Each end is exact to the round-off of
// |b| / a, the interval's scale, though an end near t = 0 loses relative digits.
struct Roots {
  double entry, exit;
};
inline Roots direct_roots(const Quadratic& q, double root_disc) {
  return {(-q.b - root_disc) / q.a, (-q.b + root_disc) / q.a};
}

}  // namespace ballagg::crossing
