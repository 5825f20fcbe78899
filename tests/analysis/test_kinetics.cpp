// The kinetic exponents on synthetic series with known exponents, the automatic window's
// rule, and the scaling collapse of size distributions that obey the scaling form.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "ballagg/analysis/kinetics.hpp"

namespace ballagg {
namespace {

// n(t) = n0 t^-z and E(t) = e0 t^-theta after t = 1, constant before (the early plateau
// a real run has), at dense, uneven times.
KineticSeries synthetic(double n0, double z, double theta, double t_end) {
  KineticSeries s;
  for (double t = 0.0; t <= t_end; t += 0.01 * (1.0 + t)) {
    s.time.push_back(t);
    s.clusters.push_back(n0 / std::pow(std::max(t, 1.0), z));
    s.energy.push_back(50.0 / std::pow(std::max(t, 1.0), theta));
  }
  return s;
}

TEST(Kinetics, FitsTheExponentsOfPowerLaws) {
  const KineticSeries s = synthetic(1e5, 1.2, 1.5, 1e4);
  const Kinetics k = fit_kinetics(s, std::pair{1e2, 1e4});
  EXPECT_NEAR(k.clusters.exponent, 1.2, 1e-9);
  EXPECT_NEAR(k.energy.exponent, 1.5, 1e-9);
  EXPECT_EQ(k.clusters.flaw, FitFlaw::none);
  EXPECT_FALSE(k.automatic_window);
  EXPECT_GE(k.clusters.fit->points, kMinFitPoints);
}

TEST(Kinetics, TheAutomaticWindowOpensAtATenthAndClosesAtTwentyClusters) {
  const KineticSeries s = synthetic(1e4, 1.0, 1.0, 1e4);
  const Kinetics k = fit_kinetics(s, std::nullopt);
  EXPECT_TRUE(k.automatic_window);
  // n = 10^4 / t: a tenth at t = 10, twenty clusters at t = 500 (to the series' spacing).
  EXPECT_NEAR(k.window_start, 10.0, 0.15);
  EXPECT_NEAR(k.window_end, 500.0, 5.0);
  EXPECT_NEAR(k.clusters.exponent, 1.0, 1e-9);
  // A run that never gets below a tenth of its clusters has no window: withheld.
  const Kinetics none = fit_kinetics(synthetic(1e4, 1.0, 1.0, 5.0), std::nullopt);
  EXPECT_TRUE(std::isnan(none.clusters.exponent));
  EXPECT_EQ(none.clusters.flaw, FitFlaw::too_few_points);
}

TEST(Kinetics, MeanFieldExponentsOfCoalescingSpheres) {
  EXPECT_DOUBLE_EQ(mean_field_z(2, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(mean_field_z(3, 3.0), 1.2);
}

TEST(Kinetics, DistributionsOfTheScalingFormCollapseOntoOneCurve) {
  // n_k = N / S^2 f(k / S) with f(x) = exp(-x), at two times with mean sizes 40 and 160:
  // both collapse onto f (the discrete mean size is S + 1/2, a relative 1/(2S) off).
  auto spectrum = [](double s, double spheres) {
    std::vector<MassSpectrumBin> bins;
    for (int k = 1; k <= 10 * s; ++k)
      bins.push_back({k, static_cast<double>(k), std::llround(spheres / (s * s) * std::exp(-k / s))});
    return bins;
  };
  for (double s : {40.0, 160.0}) {
    const std::vector<CollapsePoint> p = scaling_collapse(1.0, spectrum(s, 1e9));
    ASSERT_FALSE(p.empty());
    EXPECT_NEAR(p.front().mean_size, s + 0.5, 0.02 * s);
    for (const CollapsePoint& q : p) {
      if (q.scaled_size <= 3.0) {
        EXPECT_NEAR(q.scaled_count, std::exp(-q.scaled_size), 0.03) << s << " " << q.size;
      }
    }
  }
  EXPECT_TRUE(scaling_collapse(0.0, {}).empty());
}

}  // namespace
}  // namespace ballagg
