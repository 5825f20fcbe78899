// A prediction against a horizon (collision/prediction.hpp, contact_time_within): a
// contact up to the horizon comes back bit for bit as without it, and only a contact
// certainly later is left out. This is what keeps the event sequence of a calendar that
// keeps each cluster's earliest event unchanged when its predictions skip later contacts.
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/collision/prediction.hpp"
#include "support.hpp"

namespace ballagg {
namespace {
using testing::vec;

constexpr double kBelow = -std::numeric_limits<double>::infinity();

// The horizons that test a contact at time t hardest: t itself, the doubles next to it,
// and a little further on either side.
std::vector<double> horizons_around(double t) {
  return {t, std::nextafter(t, kBelow), std::nextafter(t, kNever), t * (1 - 1e-13), t * (1 + 1e-13),
          t * (1 - 1e-9), t * (1 + 1e-9), 0.5 * t, 2 * t};
}

TEST(ContactTimeWithin, AnalyticHeadOnPair) {
  // The gap of 9 closes at speed 2 at t = 4.5. The test's linear bound c + 2 b t =
  // 99 - 40 t leaves the contact out for a span below 99 / 40 only; between that and 4.5
  // the contact may come back, and then exactly.
  const Vec<2> dx = vec<2>(-10, 0), dv = vec<2>(2, 0);
  EXPECT_EQ(contact_time_within<2>(dx, dv, 1.0, 4.5), 4.5);
  EXPECT_EQ(contact_time_within<2>(dx, dv, 1.0, 5.0), 4.5);
  EXPECT_EQ(contact_time_within<2>(dx, dv, 1.0, 4.0), 4.5);
  EXPECT_EQ(contact_time_within<2>(dx, dv, 1.0, 2.4), kNever);
  EXPECT_EQ(contact_time_within<2>(dx, dv, 1.0, 0.0), kNever);
  // Touching now, receding, passing by: as contact_time, whatever the span.
  EXPECT_EQ(contact_time_within<2>(vec<2>(-1, 0), vec<2>(1, 0), 1.0, 0.0), 0.0);
  EXPECT_EQ(contact_time_within<2>(vec<2>(10, 0), vec<2>(1, 0), 1.0, 100.0), kNever);
  EXPECT_EQ(contact_time_within<2>(vec<2>(-10, 1.2), vec<2>(1, 0), 1.0, 100.0), kNever);
}

// Random encounters, grazing ones included: up to the span every contact comes back bit for
// bit, and one left out is later than the span.
template <int D>
void check_random_encounters() {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int left_out = 0, kept_at_the_span = 0;
  for (int n = 0; n < 20000; ++n) {
    Vec<D> dx, dv;
    for (int a = 0; a < D; ++a) dx[a] = 5 * u(rng), dv[a] = u(rng);
    const double sigma = 1.0 + 0.5 * u(rng);
    if (n % 4 == 0) {
      // A grazing encounter: the miss distance within 1e-9 of sigma.
      const Vec<D> along = dv.normalized();
      Vec<D> side = dx - dx.dot(along) * along;
      if (side.norm() == 0.0) continue;
      side *= sigma * (1 - 1e-9 * std::abs(u(rng))) / side.norm();
      dx = side - 4 * along;
    }
    const double t = contact_time<D>(dx, dv, sigma);
    if (t == kNever) {
      for (double span : {0.0, 1.0, 1e3}) EXPECT_EQ(contact_time_within<D>(dx, dv, sigma, span), kNever);
      continue;
    }
    for (double span : horizons_around(t)) {
      const double within = contact_time_within<D>(dx, dv, sigma, span);
      if (t <= span) {
        EXPECT_EQ(within, t) << "contact at " << t << " left out at span " << span;
        kept_at_the_span += span == t;
      } else if (within == kNever) {
        ++left_out;
      } else {
        EXPECT_EQ(within, t);
      }
    }
  }
  EXPECT_GT(left_out, 2000);  // the test does discard later contacts
  EXPECT_GT(kept_at_the_span, 2000);
}

TEST(ContactTimeWithin, KeepsEveryContactUpToTheSpanBitForBit2D) { check_random_encounters<2>(); }
TEST(ContactTimeWithin, KeepsEveryContactUpToTheSpanBitForBit3D) { check_random_encounters<3>(); }

// The same through predicted_contact, with anchors at different times far from 0 (where
// the absolute times round coarsely) and periodic images.
template <int D>
void check_predictions(Boundary boundary) {
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Box<D> box{20.0, boundary};
  int found = 0;
  for (int n = 0; n < 20000; ++n) {
    Cluster<D> ci, cj;
    Vec<D> oi, oj;
    for (int a = 0; a < D; ++a) {
      ci.anchor[a] = 10 + 9 * u(rng);
      cj.anchor[a] = ci.anchor[a] + 2 * u(rng);
      ci.velocity[a] = u(rng), cj.velocity[a] = u(rng);
      oi[a] = 0.3 * u(rng), oj[a] = 0.3 * u(rng);
    }
    ci.anchor_time = 1e4 + 0.1 * u(rng);
    cj.anchor_time = 1e4 + 0.1 * u(rng);
    const double now = 1e4 + 0.2;
    const double sigma = 0.8;
    const double t = predicted_contact(box, ci, oi, cj, oj, sigma, now, kNever);
    if (t == kNever) continue;
    ++found;
    for (double horizon : horizons_around(t)) {
      const double p = predicted_contact(box, ci, oi, cj, oj, sigma, now, kNever, horizon);
      if (t <= horizon) EXPECT_EQ(p, t) << "contact at " << t << " left out at horizon " << horizon;
      else EXPECT_TRUE(p == kNever || p == t);
    }
  }
  EXPECT_GT(found, 500);
}

TEST(PredictedContact, AHorizonLeavesOutOnlyLaterContactsWalls2D) { check_predictions<2>(Boundary::walls); }
TEST(PredictedContact, AHorizonLeavesOutOnlyLaterContactsWalls3D) { check_predictions<3>(Boundary::walls); }
TEST(PredictedContact, AHorizonLeavesOutOnlyLaterContactsPeriodic2D) { check_predictions<2>(Boundary::periodic); }
TEST(PredictedContact, AHorizonLeavesOutOnlyLaterContactsPeriodic3D) { check_predictions<3>(Boundary::periodic); }

}  // namespace
}  // namespace ballagg
