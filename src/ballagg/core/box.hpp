#pragma once
// The simulation box [0, L]^D and its boundary: specular walls (rule 2.2) or periodic
// faces with minimum-image geometry.
#include <cmath>
#include <string_view>

#include "ballagg/core/vec.hpp"

namespace ballagg {

// x rounded to the nearest integer, ties to even, for |x| < 2^51: adding and subtracting
// 1.5 * 2^52 leaves no fraction bits. Exact IEEE arithmetic, so identical on every machine,
// and a few instructions where std::nearbyint and std::floor are library calls on
// baseline x86-64 (this is the minimum-image hot path). Without -ffast-math the compiler
// must keep both roundings.
inline double round_to_integer(double x) {
  constexpr double kShifter = 6755399441055744.0;  // 1.5 * 2^52
  return (x + kShifter) - kShifter;
}
inline double floor_to_integer(double x) {
  const double r = round_to_integer(x);
  return r > x ? r - 1.0 : r;
}

enum class Boundary { walls, periodic };

constexpr std::string_view to_string(Boundary b) { return b == Boundary::walls ? "walls" : "periodic"; }

template <int D>
struct Box {
  double length = 1.0;
  Boundary boundary = Boundary::walls;

  bool periodic() const { return boundary == Boundary::periodic; }

  double volume() const { return std::pow(length, D); }

  // Folds a coordinate into [0, L) (periodic boxes only; walls leave it alone).
  double wrap(double x) const {
    if (!periodic()) return x;
    double w = x - length * floor_to_integer(x / length);
    return w >= length ? 0.0 : w;  // x just below 0 can round to exactly L
  }
  Vec<D> wrap(Vec<D> x) const {
    for (int a = 0; a < D; ++a) x[a] = wrap(x[a]);
    return x;
  }

  // The separation a - b: with periodic faces, the shortest image of it.
  Vec<D> separation(const Vec<D>& a, const Vec<D>& b) const {
    Vec<D> d = a - b;
    if (periodic()) {
      for (int k = 0; k < D; ++k) d[k] -= length * round_to_integer(d[k] / length);
    }
    return d;
  }
};

}  // namespace ballagg
