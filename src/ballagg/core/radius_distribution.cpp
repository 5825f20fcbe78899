#include "ballagg/core/radius_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {
namespace {

// The standard normal distribution function.
double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }

// Inverse distribution function of n(R) ~ R^-alpha on [lo, hi] at u in [0, 1), written
// relative to lo so that no power of a radius itself is formed (they could overflow).
double power_law_radius(double lo, double hi, double alpha, double u) {
  const double ratio = hi / lo;
  if (alpha == 1.0) return lo * std::pow(ratio, u);
  const double q = 1.0 - alpha;
  return lo * std::pow(1.0 + u * (std::pow(ratio, q) - 1.0), 1.0 / q);
}

}  // namespace

double truncation_acceptance(const RadiusDistribution& d, double reference_radius) {
  if (d.law == RadiusLaw::lognormal) {
    const double s = std::log(d.sigma);
    const double lo = d.min > 0.0 ? normal_cdf(std::log(d.min / reference_radius) / s) : 0.0;
    const double hi = std::isinf(d.max) ? 1.0 : normal_cdf(std::log(d.max / reference_radius) / s);
    return hi - lo;
  }
  if (d.law == RadiusLaw::normal) {
    // Radii <= 0 are redrawn too: the lower end is never below 0.
    const double lo = normal_cdf((std::max(d.min, 0.0) - reference_radius) / d.sigma);
    const double hi = std::isinf(d.max) ? 1.0 : normal_cdf((d.max - reference_radius) / d.sigma);
    return hi - lo;
  }
  return 1.0;
}

RadiusSampler::RadiusSampler(const RadiusDistribution& d, double reference_radius, std::uint64_t seed)
    : d_(d), r0_(reference_radius), rng_(seed, RandomPurpose::radii) {
  if (d.law != RadiusLaw::discrete) return;
  double sum = 0.0;
  for (std::size_t k = 0; k < d.radii.size(); ++k) {
    sum += d.weights.empty() ? 1.0 : d.weights[k];
    cumulative_.push_back(sum);
  }
}

double RadiusSampler::untruncated() {
  switch (d_.law) {
    case RadiusLaw::monodisperse:
      return r0_;
    case RadiusLaw::lognormal:  // ln R normal with mean ln R_0 and standard deviation ln sigma_g
      return r0_ * std::exp(std::log(d_.sigma) * rng_.normal());
    case RadiusLaw::normal:
      return r0_ + d_.sigma * rng_.normal();
    case RadiusLaw::uniform:
      return rng_.uniform(d_.min, d_.max);
    case RadiusLaw::power_law:
      return power_law_radius(d_.min, d_.max, d_.exponent, rng_.uniform());
    case RadiusLaw::discrete: {
      const double u = rng_.uniform() * cumulative_.back();
      const auto k = std::upper_bound(cumulative_.begin(), cumulative_.end(), u) - cumulative_.begin();
      return d_.radii[std::min<std::size_t>(static_cast<std::size_t>(k), d_.radii.size() - 1)];
    }
  }
  return r0_;
}

double RadiusSampler::next() {
  const bool truncated = d_.law == RadiusLaw::lognormal || d_.law == RadiusLaw::normal;
  if (!truncated) return untruncated();
  for (int draw = 0; draw < kMaxTruncationDraws; ++draw) {
    const double r = untruncated();
    if (r > 0.0 && r >= d_.min && r <= d_.max) return r;
  }
  throw InputError(fmt::format("system.radius_min = {}, system.radius_max = {}: no radius of the law fell in this "
                               "range in {} draws; widen it", d_.min, d_.max, kMaxTruncationDraws));
}

std::vector<double> sample_radii(const RadiusDistribution& d, double reference_radius, std::int64_t n,
                                 std::uint64_t seed) {
  if (d.law == RadiusLaw::monodisperse) return std::vector<double>(static_cast<std::size_t>(n), reference_radius);
  RadiusSampler sampler(d, reference_radius, seed);
  std::vector<double> r(static_cast<std::size_t>(n));
  for (double& ri : r) ri = sampler.next();
  return r;
}

double sphere_volume(int dimension, double r) {
  return dimension == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
}

}  // namespace ballagg
