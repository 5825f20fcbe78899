#pragma once
// The simulation box [0, L]^D and its boundary: specular walls (rule 2.2) or periodic
// faces with minimum-image geometry.
#include <cmath>
#include <string_view>

#include "ballagg/core/vec.hpp"

namespace ballagg {

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
    double w = x - length * std::floor(x / length);
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
      for (int k = 0; k < D; ++k) d[k] -= length * std::nearbyint(d[k] / length);
    }
    return d;
  }
};

}  // namespace ballagg
