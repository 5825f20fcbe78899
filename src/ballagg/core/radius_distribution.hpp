#pragma once
// The law of the sphere radii of a generated start (docs/configuration.md, "Polydisperse
// spheres"): one radius for all, or a sample of N independent draws from a lognormal,
// normal, uniform, power-law or discrete law. It sits in core because both the
// configuration (the box follows from the sampled radii and the volume fraction) and the
// initial state (which places the spheres) draw the same sample.
#include <cstdint>
#include <limits>
#include <vector>

#include "ballagg/core/random.hpp"

namespace ballagg {

enum class RadiusLaw { monodisperse, lognormal, normal, uniform, power_law, discrete };

// The parameters besides the reference radius R_0 (system.radius: the one radius, the
// lognormal median, the normal mean). Unused parameters keep their defaults.
struct RadiusDistribution {
  RadiusLaw law = RadiusLaw::monodisperse;
  double sigma = 0.0;     // lognormal: geometric standard deviation (> 1); normal: standard deviation
  double min = 0.0;       // uniform, power law: bounds; lognormal, normal: truncation (0: none)
  double max = std::numeric_limits<double>::infinity();
  double exponent = 0.0;  // power law: n(R) ~ R^-exponent on [min, max]
  std::vector<double> radii;    // discrete: the radii ...
  std::vector<double> weights;  // ... and their relative frequencies (empty: equal)
};

// A truncated lognormal or normal redraws a radius outside [min, max] at most this many
// times. The configuration refuses truncations that keep less than
// kMinTruncationAcceptance of the law, so that the cap (hit with probability below
// (1 - 0.01)^100000, about 1e-436) only guards against a hang.
inline constexpr int kMaxTruncationDraws = 100000;
inline constexpr double kMinTruncationAcceptance = 0.01;

// The fraction of the untruncated lognormal (normal) law of radius R_0 and `sigma` that
// lies in [min, max].
double truncation_acceptance(const RadiusDistribution& d, double reference_radius);

// Draws radii one after the other from the stream (seed, RandomPurpose::radii): the k-th
// radius depends on the seed and k only, never on threads.
class RadiusSampler {
 public:
  RadiusSampler(const RadiusDistribution& d, double reference_radius, std::uint64_t seed);
  // Throws InputError when a truncated law finds no radius in kMaxTruncationDraws draws.
  double next();

 private:
  double untruncated();

  const RadiusDistribution& d_;
  double r0_;
  Random rng_;
  std::vector<double> cumulative_;  // discrete: cumulative weights
};

// n radii of the law (all equal to reference_radius for monodisperse).
std::vector<double> sample_radii(const RadiusDistribution& d, double reference_radius, std::int64_t n,
                                 std::uint64_t seed);

// The volume of a sphere of radius r in D dimensions: pi r^2 (2D), 4/3 pi r^3 (3D).
double sphere_volume(int dimension, double r);

}  // namespace ballagg
