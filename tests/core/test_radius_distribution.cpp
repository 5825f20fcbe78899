// The radius sampler's laws: the moments of N = 20000 draws against the analytic values,
// within kStandardErrors standard errors (the seeds are fixed, so each check passes or
// fails the same way every time; a wrong law misses by tens of standard errors).
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/core/input_error.hpp"
#include "ballagg/core/radius_distribution.hpp"

namespace ballagg {
namespace {

constexpr std::int64_t kDraws = 20000;
constexpr double kStandardErrors = 4.0;

struct Moments {
  double mean = 0.0, variance = 0.0;
};

Moments moments(const std::vector<double>& x) {
  Moments m;
  const double n = static_cast<double>(x.size());
  m.mean = std::accumulate(x.begin(), x.end(), 0.0) / n;
  for (double v : x) m.variance += (v - m.mean) * (v - m.mean);
  m.variance /= n - 1.0;
  return m;
}

// The sample mean and variance of x against a law of mean mu and variance var whose
// fourth central moment is mu4 (the standard error of a sample variance is
// sqrt((mu4 - var^2) / N)).
void expect_moments(const std::vector<double>& x, double mu, double var, double mu4) {
  const Moments m = moments(x);
  const double n = static_cast<double>(x.size());
  EXPECT_NEAR(m.mean, mu, kStandardErrors * std::sqrt(var / n));
  EXPECT_NEAR(m.variance, var, kStandardErrors * std::sqrt((mu4 - var * var) / n));
}

std::vector<double> logs(std::vector<double> x) {
  for (double& v : x) v = std::log(v);
  return x;
}

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }
double normal_pdf(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi); }

TEST(RadiusDistribution, MonodisperseGivesTheReferenceRadius) {
  const std::vector<double> r = sample_radii(RadiusDistribution{}, 0.37, 50, 3);
  EXPECT_EQ(r, std::vector<double>(50, 0.37));
}

TEST(RadiusDistribution, LognormalLogMomentsAreLnMedianAndLnGeometricSigma) {
  RadiusDistribution d;
  d.law = RadiusLaw::lognormal;
  d.sigma = 1.6;
  const double s = std::log(1.6);
  const std::vector<double> r = sample_radii(d, 2.0, kDraws, 11);
  expect_moments(logs(r), std::log(2.0), s * s, 3.0 * s * s * s * s);
  // The radius itself: mean R_0 exp(s^2 / 2).
  const Moments m = moments(r);
  const double var = 4.0 * (std::exp(s * s) - 1.0) * std::exp(s * s);
  EXPECT_NEAR(m.mean, 2.0 * std::exp(0.5 * s * s), kStandardErrors * std::sqrt(var / kDraws));
}

TEST(RadiusDistribution, NormalHasTheGivenMeanAndStandardDeviation) {
  RadiusDistribution d;
  d.law = RadiusLaw::normal;
  d.sigma = 0.1;  // radii <= 0 are 10 standard deviations away: no truncation to speak of
  expect_moments(sample_radii(d, 1.0, kDraws, 12), 1.0, 0.01, 3.0 * 1e-4);
}

TEST(RadiusDistribution, TruncatedNormalStaysInItsBoundsWithTheTruncatedMean) {
  RadiusDistribution d;
  d.law = RadiusLaw::normal;
  d.sigma = 0.5;
  d.min = 0.8;
  d.max = 1.5;
  const std::vector<double> r = sample_radii(d, 1.0, kDraws, 13);
  EXPECT_GE(*std::min_element(r.begin(), r.end()), 0.8);
  EXPECT_LE(*std::max_element(r.begin(), r.end()), 1.5);
  const double a = (0.8 - 1.0) / 0.5, b = (1.5 - 1.0) / 0.5, z = normal_cdf(b) - normal_cdf(a);
  EXPECT_NEAR(truncation_acceptance(d, 1.0), z, 1e-15);
  const double mean = 1.0 + 0.5 * (normal_pdf(a) - normal_pdf(b)) / z;
  const double var = 0.25 * (1.0 + (a * normal_pdf(a) - b * normal_pdf(b)) / z -
                             std::pow((normal_pdf(a) - normal_pdf(b)) / z, 2));
  EXPECT_NEAR(moments(r).mean, mean, kStandardErrors * std::sqrt(var / kDraws));
}

TEST(RadiusDistribution, UniformHasTheMomentsOfItsInterval) {
  RadiusDistribution d;
  d.law = RadiusLaw::uniform;
  d.min = 0.5;
  d.max = 2.0;
  const std::vector<double> r = sample_radii(d, 1.0, kDraws, 14);
  const double w = 1.5;
  expect_moments(r, 1.25, w * w / 12.0, std::pow(w, 4) / 80.0);
  EXPECT_GE(*std::min_element(r.begin(), r.end()), 0.5);
  EXPECT_LT(*std::max_element(r.begin(), r.end()), 2.0);
}

// The fraction of draws below x against F(x) of n(R) ~ R^-alpha on [a, b], at several x,
// and the bounds.
void expect_power_law(double alpha, std::uint64_t seed) {
  RadiusDistribution d;
  d.law = RadiusLaw::power_law;
  d.min = 1.0;
  d.max = 100.0;
  d.exponent = alpha;
  const std::vector<double> r = sample_radii(d, 1.0, kDraws, seed);
  EXPECT_GE(*std::min_element(r.begin(), r.end()), 1.0);
  EXPECT_LE(*std::max_element(r.begin(), r.end()), 100.0);
  const auto cdf = [&](double x) {
    if (alpha == 1.0) return std::log(x) / std::log(100.0);
    return (std::pow(x, 1.0 - alpha) - 1.0) / (std::pow(100.0, 1.0 - alpha) - 1.0);
  };
  for (double x : {1.5, 3.0, 10.0, 30.0}) {
    const double below = static_cast<double>(std::count_if(r.begin(), r.end(), [&](double v) { return v < x; }));
    const double f = cdf(x);
    EXPECT_NEAR(below / kDraws, f, kStandardErrors * std::sqrt(f * (1.0 - f) / kDraws)) << "alpha " << alpha << ", x " << x;
  }
  // The mean, E[R] = int R n(R) dR / int n(R) dR.
  const auto integral = [](double p) { return p == 0.0 ? std::log(100.0) : (std::pow(100.0, p) - 1.0) / p; };
  const double mean = integral(2.0 - alpha) / integral(1.0 - alpha);
  const double var = integral(3.0 - alpha) / integral(1.0 - alpha) - mean * mean;
  EXPECT_NEAR(moments(r).mean, mean, kStandardErrors * std::sqrt(var / kDraws)) << "alpha " << alpha;
}

TEST(RadiusDistribution, PowerLawFollowsItsDistributionFunctionBetweenItsBounds) {
  expect_power_law(2.5, 15);
  expect_power_law(1.0, 16);
  expect_power_law(-0.5, 17);
}

TEST(RadiusDistribution, DiscreteDrawsEachRadiusAtItsWeight) {
  RadiusDistribution d;
  d.law = RadiusLaw::discrete;
  d.radii = {0.5, 1.0, 2.0};
  d.weights = {1.0, 2.0, 5.0};
  const std::vector<double> r = sample_radii(d, 1.0, kDraws, 18);
  std::map<double, int> count;
  for (double v : r) ++count[v];
  ASSERT_EQ(count.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const double p = d.weights[k] / 8.0;
    EXPECT_NEAR(count[d.radii[k]] / static_cast<double>(kDraws), p, kStandardErrors * std::sqrt(p * (1 - p) / kDraws));
  }
  d.weights.clear();  // equal weights
  std::map<double, int> equal;
  for (double v : sample_radii(d, 1.0, kDraws, 19)) ++equal[v];
  for (double radius : d.radii)
    EXPECT_NEAR(equal[radius] / static_cast<double>(kDraws), 1.0 / 3.0, kStandardErrors * std::sqrt(2.0 / 9.0 / kDraws));
}

TEST(RadiusDistribution, SameSeedSameRadiiOtherSeedOthers) {
  RadiusDistribution d;
  d.law = RadiusLaw::lognormal;
  d.sigma = 1.3;
  EXPECT_EQ(sample_radii(d, 1.0, 1000, 7), sample_radii(d, 1.0, 1000, 7));
  EXPECT_NE(sample_radii(d, 1.0, 1000, 7), sample_radii(d, 1.0, 1000, 8));
  // The k-th radius does not depend on how many are drawn.
  const std::vector<double> more = sample_radii(d, 1.0, 2000, 7);
  EXPECT_EQ(std::vector<double>(more.begin(), more.begin() + 1000), sample_radii(d, 1.0, 1000, 7));
}

TEST(RadiusDistribution, ATruncationThatKeepsNothingEndsWithAnError) {
  RadiusDistribution d;
  d.law = RadiusLaw::normal;
  d.sigma = 0.01;
  d.min = 5.0;  // 400 standard deviations above the mean: never drawn
  d.max = 6.0;
  EXPECT_LT(truncation_acceptance(d, 1.0), kMinTruncationAcceptance);
  EXPECT_THROW(sample_radii(d, 1.0, 1, 1), InputError);
}

TEST(RadiusDistribution, SphereVolumes) {
  EXPECT_DOUBLE_EQ(sphere_volume(2, 2.0), 4.0 * std::numbers::pi);
  EXPECT_DOUBLE_EQ(sphere_volume(3, 2.0), 32.0 / 3.0 * std::numbers::pi);
}

}  // namespace
}  // namespace ballagg
