// Contact times (paper eq. A.1-A.3) against hand-computed answers.
#include <cmath>

#include <gtest/gtest.h>

#include "ballagg/collision/contact_time.hpp"
#include "support.hpp"

namespace ballagg {
namespace {
using testing::vec;

TEST(ContactTime, HeadOnPairMeetsAtAnalyticTime2D) {
  // Centres 10 apart, radii 0.5 each, closing at speed 2: the gap of 9 closes at t = 4.5.
  EXPECT_DOUBLE_EQ(contact_time<2>(vec<2>(-10, 0), vec<2>(2, 0), 1.0), 4.5);
}

TEST(ContactTime, HeadOnPairMeetsAtAnalyticTime3D) {
  EXPECT_DOUBLE_EQ(contact_time<3>(vec<3>(0, 0, -6), vec<3>(0, 0, 0.5), 2.0), 8.0);
}

TEST(ContactTime, ObliquePairMeetsWhereTheImpactParameterAllows2D) {
  // Impact parameter 0.6, sigma 1: contact when the along-track distance is 0.8.
  EXPECT_NEAR(contact_time<2>(vec<2>(-10, 0.6), vec<2>(1, 0), 1.0), 9.2, 1e-13);
}

TEST(ContactTime, ObliquePairMeetsWhereTheImpactParameterAllows3D) {
  // Impact parameter |(0.3, 0.4)| = 0.5, sigma 1: along-track distance sqrt(0.75).
  EXPECT_NEAR(contact_time<3>(vec<3>(-10, 0.3, 0.4), vec<3>(1, 0, 0), 1.0), 10 - std::sqrt(0.75), 1e-13);
  // The same encounter seen with the velocity along a diagonal.
  const Vec<3> dir = vec<3>(1, 1, 1).normalized();
  const Vec<3> perp = vec<3>(1, -1, 0).normalized() * 0.5;
  EXPECT_NEAR(contact_time<3>(-10 * dir + perp, 2 * dir, 1.0), (10 - std::sqrt(0.75)) / 2, 1e-12);
}

TEST(ContactTime, AgreesWithThePapersFormula) {
  // (A.3): t = -(b + sqrt(b^2 - a c)) / a, computed here in long double.
  const Vec<2> dx = vec<2>(-3.7, 1.1), dv = vec<2>(0.9, -0.2);
  const long double b = dx.dot(dv), a = dv.squaredNorm(), c = dx.squaredNorm() - 1.0;
  const long double paper = -(b + std::sqrt(b * b - a * c)) / a;
  EXPECT_NEAR(contact_time<2>(dx, dv, 1.0), static_cast<double>(paper), 1e-14);
}

TEST(ContactTime, MissingRecedingAndParallelPairsNeverTouch) {
  EXPECT_EQ(contact_time<2>(vec<2>(-10, 1.2), vec<2>(1, 0), 1.0), kNever);  // passes by
  EXPECT_EQ(contact_time<2>(vec<2>(10, 0), vec<2>(1, 0), 1.0), kNever);     // recedes
  EXPECT_EQ(contact_time<2>(vec<2>(-10, 0), vec<2>(0, 0), 1.0), kNever);    // no relative motion
  EXPECT_EQ(contact_time<3>(vec<3>(0, 1, 0), vec<3>(1, 0, 0), 1.0), kNever);  // grazing contact
}

TEST(ContactTime, TouchingApproachingPairTouchesNow) {
  EXPECT_EQ(contact_time<2>(vec<2>(-1, 0), vec<2>(1, 0), 1.0), 0.0);
  // Overlapping by round-off and still approaching: now, never a negative time.
  EXPECT_EQ(contact_time<2>(vec<2>(-1 + 1e-15, 0), vec<2>(1, 0), 1.0), 0.0);
}

TEST(ContactTime, FarPairKeepsFullPrecision) {
  // The textbook form loses digits to cancellation here; ours must not.
  EXPECT_EQ(contact_time<2>(vec<2>(-1e7, 0), vec<2>(1, 0), 1.0), 1e7 - 1);
  EXPECT_NEAR(contact_time<2>(vec<2>(-1e7, 0.5), vec<2>(1, 0), 1.0), 1e7 - std::sqrt(0.75), 1e-8);
}

}  // namespace
}  // namespace ballagg
