#pragma once
// Reproducible random numbers. Every consumer draws from its own PCG stream selected by
// (seed, purpose), so adding a new random quantity never shifts the draws of another one,
// and the conversions to doubles are our own (the standard library's distributions are
// implementation-defined and would make results depend on the compiler).
#include <cmath>
#include <cstdint>
#include <numbers>

#include <pcg_random.hpp>

#include "ballagg/core/vec.hpp"

namespace ballagg {

enum class RandomPurpose : std::uint64_t {
  positions = 1,
  velocities = 2,
  radii = 3,
};

class Random {
 public:
  Random(std::uint64_t seed, RandomPurpose purpose)
      : engine_(seed, static_cast<std::uint64_t>(purpose)) {}

  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  // Standard normal by the Box-Muller transform (both values of a pair are not reused:
  // one draw per call keeps the stream position a simple function of the call count).
  double normal() {
    const double u1 = 1.0 - uniform();  // in (0, 1], so the log is finite
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

  // Direction uniformly distributed on the unit circle (D = 2, eq. 4.2) or sphere (D = 3).
  template <int D>
  Vec<D> unit_vector() {
    const double phi = 2.0 * std::numbers::pi * uniform();
    Vec<D> u;
    if constexpr (D == 2) {
      u << std::cos(phi), std::sin(phi);
    } else {
      const double z = uniform(-1.0, 1.0);
      const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
      u << rho * std::cos(phi), rho * std::sin(phi), z;
    }
    return u;
  }

 private:
  pcg64 engine_;
};

}  // namespace ballagg
