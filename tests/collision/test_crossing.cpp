// The crossing kernel: the roots of |d + t v| = r (collision/crossing.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "ballagg/collision/crossing.hpp"

namespace ballagg {
namespace {

TEST(Crossing, EntryAndExitOfAHeadOnPassAreTheTwoSurfaceInstants) {
  // A point 5 away moving at speed 2 straight through a sphere of radius 1: it enters at
  // t = 2 and leaves at t = 3.
  const crossing::Quadratic q = crossing::quadratic(Vec<3>(5.0, 0.0, 0.0), Vec<3>(-2.0, 0.0, 0.0), 1.0);
  const double root = std::sqrt(crossing::discriminant(q));
  EXPECT_DOUBLE_EQ(crossing::entry(q, root), 2.0);
  EXPECT_DOUBLE_EQ(crossing::exit(q, root), 3.0);
  const crossing::Roots direct = crossing::direct_roots(q, root);
  EXPECT_DOUBLE_EQ(direct.entry, 2.0);
  EXPECT_DOUBLE_EQ(direct.exit, 3.0);
}

TEST(Crossing, RecedingPointInsideLeavesAtTheLaterRootAndEnteredInThePast) {
  // From the centre's side, 0.5 inside, moving out at speed 1 along x: exit at t = 0.5,
  // entry (backwards in time) at t = -1.5.
  const crossing::Quadratic q = crossing::quadratic(Vec<2>(0.5, 0.0), Vec<2>(1.0, 0.0), 1.0);
  const double root = std::sqrt(crossing::discriminant(q));
  EXPECT_DOUBLE_EQ(crossing::exit(q, root), 0.5);
  EXPECT_DOUBLE_EQ(crossing::entry(q, root), -1.5);
}

TEST(Crossing, AMissHasANegativeDiscriminant) {
  const crossing::Quadratic q = crossing::quadratic(Vec<2>(5.0, 2.0), Vec<2>(-1.0, 0.0), 1.0);
  EXPECT_LT(crossing::discriminant(q), 0.0);
}

TEST(Crossing, CancellationFreeRootsAreTheRootsOfTheQuadratic) {
  // Over a spread of places and velocities, each root puts the point on the surface.
  for (int k = 0; k < 200; ++k) {
    const Vec<3> d(std::sin(1.3 * k) * 4.0, std::cos(0.7 * k) * 3.0, std::sin(0.31 * k + 1.0) * 2.0);
    const Vec<3> v(std::cos(2.1 * k), std::sin(0.9 * k), std::cos(0.37 * k));
    const double r = 0.5 + 0.25 * std::cos(0.11 * k);
    const crossing::Quadratic q = crossing::quadratic(d, v, r);
    const double disc = crossing::discriminant(q);
    if (disc < 0.0) continue;
    for (const double t : {crossing::entry(q, std::sqrt(disc)), crossing::exit(q, std::sqrt(disc))})
      EXPECT_NEAR((d + t * v).norm(), r, 1e-12) << "case " << k << ", t = " << t;
  }
}

}  // namespace
}  // namespace ballagg
