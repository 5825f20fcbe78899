// The collision laws (rules 2.2, 2.6-2.9) as statements of conservation and restitution.
#include <gtest/gtest.h>

#include "ballagg/collision/laws.hpp"
#include "support.hpp"

namespace ballagg {
namespace {
using testing::vec;

TEST(CollisionLaws, StickingMovesWithTheMassWeightedMeanVelocity) {
  const Vec<3> v = stick_velocity<3>(1.0, vec<3>(1, 0, 0), 3.0, vec<3>(0, -1, 2));
  EXPECT_DOUBLE_EQ(v[0], 0.25);
  EXPECT_DOUBLE_EQ(v[1], -0.75);
  EXPECT_DOUBLE_EQ(v[2], 1.5);
}

TEST(CollisionLaws, BounceConservesMomentumForUnequalMasses) {
  // The paper's (2.7) as extracted would give alpha = m1/(m1+m2), which does not conserve
  // momentum when m1 != m2; our law must.
  const double m1 = 1.0, m2 = 3.0;
  Vec<2> v1 = vec<2>(2, 1), v2 = vec<2>(-1, 0.5);
  const Vec<2> p = m1 * v1 + m2 * v2;
  bounce_velocities<2>(m1, v1, m2, v2, vec<2>(-1, 0), 0.5);
  const Vec<2> q = m1 * v1 + m2 * v2;
  EXPECT_NEAR((q - p).norm(), 0.0, 1e-15);
}

TEST(CollisionLaws, BounceReversesNormalVelocityTimesRestitutionAndKeepsTangential) {
  const Vec<2> n = vec<2>(3, 4).normalized();
  for (double eps : {0.0, 0.3, 1.0}) {
    Vec<2> v1 = vec<2>(-1, -2), v2 = vec<2>(0.5, 0.1);
    const double g = (v1 - v2).dot(n);
    const Vec<2> tangent = vec<2>(-4, 3).normalized();
    const double t1 = v1.dot(tangent), t2 = v2.dot(tangent);
    bounce_velocities<2>(2.0, v1, 0.7, v2, n, eps);
    EXPECT_NEAR((v1 - v2).dot(n), -eps * g, 1e-15);
    EXPECT_NEAR(v1.dot(tangent), t1, 1e-15);
    EXPECT_NEAR(v2.dot(tangent), t2, 1e-15);
  }
}

TEST(CollisionLaws, BounceDissipatesTheEnergyOfEquation2_8) {
  // (2.8): loss of sum m|V|^2 is 4 mu beta (1 - beta) g^2 with mu the reduced mass.
  const double m1 = 1.5, m2 = 0.5, eps = 0.4, beta = (1 - eps) / 2;
  const Vec<3> n = vec<3>(1, 2, 2).normalized();
  Vec<3> v1 = vec<3>(-1, -1, 0), v2 = vec<3>(1, 0, 1);
  const double g = (v1 - v2).dot(n);
  const double before = m1 * v1.squaredNorm() + m2 * v2.squaredNorm();
  bounce_velocities<3>(m1, v1, m2, v2, n, eps);
  const double after = m1 * v1.squaredNorm() + m2 * v2.squaredNorm();
  EXPECT_NEAR(after - before, -4 * (m1 * m2 / (m1 + m2)) * beta * (1 - beta) * g * g, 1e-14);
}

TEST(CollisionLaws, SeparatingBodiesDoNotBounce) {
  Vec<2> v1 = vec<2>(1, 0), v2 = vec<2>(-1, 0);
  bounce_velocities<2>(1.0, v1, 1.0, v2, vec<2>(1, 0), 0.5);  // n from 2 to 1: moving apart
  EXPECT_EQ(v1, vec<2>(1, 0));
  EXPECT_EQ(v2, vec<2>(-1, 0));
}

TEST(CollisionLaws, WallReflectionFlipsOnlyTheNormalComponent) {
  EXPECT_EQ(reflect_velocity<3>(vec<3>(1, -2, 3), 1), vec<3>(1, 2, 3));
}

}  // namespace
}  // namespace ballagg
