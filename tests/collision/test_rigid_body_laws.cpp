// Collision laws of rotating rigid bodies (Richardson 1995 §2.4-2.5): the impulse with
// generalised coefficients (13)-(19) and its closed form (23)-(28), coagulation (8)-(12),
// and the Bridges et al. ice law of the normal coefficient.
#include <cmath>

#include <gtest/gtest.h>

#include "ballagg/collision/rigid_coagulation.hpp"
#include "ballagg/collision/rigid_impulse.hpp"
#include "ballagg/core/random.hpp"

namespace ballagg {
namespace {

// A random body with a random (symmetric positive definite) inertia tensor.
struct Body3 {
  double mass;
  Vec<3> centre, velocity, omega;
  InertiaTensor<3> inertia;
  Vec<3> momentum() const { return mass * velocity; }
  Vec<3> angular_momentum() const { return mass * centre.cross(velocity) + inertia * omega; }
  double energy() const { return 0.5 * mass * velocity.squaredNorm() + 0.5 * omega.dot(inertia * omega); }
};

Body3 random_body(Random& rng, const Vec<3>& centre) {
  Body3 b;
  b.mass = rng.uniform(0.5, 5.0);
  b.centre = centre;
  b.velocity = Vec<3>(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  b.omega = Vec<3>(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
  const Rotation<3> axes = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
  b.inertia = axes * Vec<3>(rng.uniform(0.2, 1.0), rng.uniform(0.2, 1.0), rng.uniform(0.2, 1.0)).asDiagonal() * axes.transpose();
  return b;
}

ImpactBody<3> impact_body(const Body3& b, const Vec<3>& contact) {
  return {1.0 / b.mass, b.inertia.inverse(), b.velocity, b.omega, contact - b.centre};
}

// Applies the impulse P of the law to both bodies, (13)-(14).
void apply(Body3& b1, Body3& b2, const Vec<3>& contact, const Vec<3>& p) {
  b1.velocity += p / b1.mass;
  b1.omega += b1.inertia.inverse() * (contact - b1.centre).cross(p);
  b2.velocity -= p / b2.mass;
  b2.omega -= b2.inertia.inverse() * (contact - b2.centre).cross(p);
}

// Two bodies with an off-centre contact at which they approach.
struct Collision {
  Body3 b1, b2;
  Vec<3> contact, n;
};
Collision approaching_pair(Random& rng) {
  while (true) {
    Collision s;
    s.b1 = random_body(rng, Vec<3>(0.0, 0.1, -0.2));
    s.b2 = random_body(rng, Vec<3>(2.0, -0.3, 0.4));
    s.contact = Vec<3>(1.0, 0.5, 0.3);
    s.n = Vec<3>(1.0, 0.2, -0.1).normalized();
    const ImpactBody<3> i1 = impact_body(s.b1, s.contact), i2 = impact_body(s.b2, s.contact);
    if ((i2.contact_velocity() - i1.contact_velocity()).dot(s.n) < -0.1) return s;
  }
}

TEST(RigidImpulse, OffCentreRestitutionConservesMomentumAndAngularMomentum) {
  Random rng(11, RandomPurpose::positions);
  for (int trial = 0; trial < 200; ++trial) {
    Collision s = approaching_pair(rng);
    const ImpactCoefficients k{rng.uniform(0.0, 1.0), 0.0, 0.0};
    const Impact<3> impact = collision_impulse(impact_body(s.b1, s.contact), impact_body(s.b2, s.contact), s.n, k);
    ASSERT_TRUE(impact.approaching);
    const Vec<3> p0 = s.b1.momentum() + s.b2.momentum();
    const Vec<3> l0 = s.b1.angular_momentum() + s.b2.angular_momentum();
    const double e0 = s.b1.energy() + s.b2.energy();
    const double scale_p = s.b1.mass * s.b1.velocity.norm() + s.b2.mass * s.b2.velocity.norm();
    const double scale_l = l0.norm() + s.b1.angular_momentum().norm() + s.b2.angular_momentum().norm();
    apply(s.b1, s.b2, s.contact, impact.impulse);
    EXPECT_LT((s.b1.momentum() + s.b2.momentum() - p0).norm(), 1e-12 * scale_p);
    EXPECT_LT((s.b1.angular_momentum() + s.b2.angular_momentum() - l0).norm(), 1e-12 * scale_l);
    // (15): the normal relative velocity at the contact is reversed and scaled by eps_n.
    const double un = (impact_body(s.b2, s.contact).contact_velocity() - impact_body(s.b1, s.contact).contact_velocity()).dot(s.n);
    EXPECT_NEAR(un, -k.normal_restitution * impact.normal_velocity, 1e-12 * std::abs(impact.normal_velocity));
    // Energy: lost as (1 - eps^2) / 2 of the normal impact energy, as returned.
    const double e1 = s.b1.energy() + s.b2.energy();
    EXPECT_NEAR(e1 - e0, impact.energy_change, 1e-12 * e0);
    EXPECT_NEAR(impact.energy_change,
                -0.5 * (1 - k.normal_restitution * k.normal_restitution) * impact.normal_velocity * impact.normal_velocity /
                    impact.denominator,
                1e-12 * e0);
  }
}

TEST(RigidImpulse, ElasticFrictionlessImpactConservesEnergyAndInelasticDissipates) {
  Random rng(12, RandomPurpose::positions);
  for (int trial = 0; trial < 100; ++trial) {
    const Collision s = approaching_pair(rng);
    const double e0 = s.b1.energy() + s.b2.energy();
    const Impact<3> elastic = collision_impulse(impact_body(s.b1, s.contact), impact_body(s.b2, s.contact), s.n, {1.0, 0, 0});
    EXPECT_LT(std::abs(elastic.energy_change), 1e-13 * e0);
    const Impact<3> inelastic = collision_impulse(impact_body(s.b1, s.contact), impact_body(s.b2, s.contact), s.n, {0.5, 0, 0});
    EXPECT_LT(inelastic.energy_change, -1e-6 * e0);
  }
}

TEST(RigidImpulse, ClosedFormMatchesRichardsonsEquations23To28) {
  Random rng(13, RandomPurpose::positions);
  for (int trial = 0; trial < 50; ++trial) {
    const Collision s = approaching_pair(rng);
    const double eps = 0.7;
    // The ntp basis (Appendix): n, then t and p by Gram-Schmidt; the inverse inertia
    // tensors in that basis (33); gamma from (24); dv1 from (25), dw from (27)-(28).
    Rotation<3> b;
    b.col(0) = s.n;
    b.col(1) = (Vec<3>::UnitZ() - Vec<3>::UnitZ().dot(s.n) * s.n).normalized();
    b.col(2) = b.col(0).cross(b.col(1));
    const InertiaTensor<3> a = b.transpose() * s.b1.inertia.inverse() * b, bb = b.transpose() * s.b2.inertia.inverse() * b;
    const Vec<3> c1 = b.transpose() * (s.contact - s.b1.centre), c2 = b.transpose() * (s.contact - s.b2.centre);
    const double m1 = s.b1.mass, m2 = s.b2.mass, big_m = m1 + m2, mu = m1 * m2 / big_m;
    const double gamma_inverse = 1.0 + mu * (a(1, 1) * c1[2] * c1[2] - 2 * a(1, 2) * c1[1] * c1[2] + a(2, 2) * c1[1] * c1[1] +
                                             bb(1, 1) * c2[2] * c2[2] - 2 * bb(1, 2) * c2[1] * c2[2] + bb(2, 2) * c2[1] * c2[1]);
    const ImpactBody<3> i1 = impact_body(s.b1, s.contact), i2 = impact_body(s.b2, s.contact);
    const double un = (i2.contact_velocity() - i1.contact_velocity()).dot(s.n);
    const Vec<3> dv1 = (1 + eps) * (m2 / big_m) * un / gamma_inverse * s.n;  // (25)
    const Vec<3> dw1 = m1 * s.b1.inertia.inverse() * (s.contact - s.b1.centre).cross(dv1);  // (27)
    const Vec<3> dw2 = -m1 * s.b2.inertia.inverse() * (s.contact - s.b2.centre).cross(dv1);  // (28)
    const Impact<3> impact = collision_impulse(i1, i2, s.n, {eps, 0, 0});
    EXPECT_LT((impact.impulse / m1 - dv1).norm(), 1e-12 * dv1.norm());
    EXPECT_LT((-impact.impulse / m2 + m1 / m2 * dv1).norm(), 1e-12 * dv1.norm());  // (26)
    EXPECT_LT((s.b1.inertia.inverse() * (s.contact - s.b1.centre).cross(impact.impulse) - dw1).norm(), 1e-12 * dw1.norm());
    EXPECT_LT((-s.b2.inertia.inverse() * (s.contact - s.b2.centre).cross(impact.impulse) - dw2).norm(), 1e-12 * dw2.norm());
  }
}

TEST(RigidImpulse, FrictionOpposesTheSlipAndConservesMomenta) {
  Random rng(14, RandomPurpose::positions);
  for (int trial = 0; trial < 100; ++trial) {
    Collision s = approaching_pair(rng);
    const ImpactBody<3> i1 = impact_body(s.b1, s.contact), i2 = impact_body(s.b2, s.contact);
    const Vec<3> u = i2.contact_velocity() - i1.contact_velocity();
    const Vec<3> slip = -(u - u.dot(s.n) * s.n);  // body 1 over body 2
    const Impact<3> impact = collision_impulse(i1, i2, s.n, {0.6, 0.3, 0.0});
    ASSERT_GT(impact.denominator, 0.0);
    // The tangential impulse on body 1 points against its slip.
    const Vec<3> tangential = impact.impulse - impact.impulse.dot(s.n) * s.n;
    EXPECT_LT(tangential.dot(slip), 0.0);
    EXPECT_NEAR(tangential.norm(), 0.3 * std::abs(impact.impulse.dot(s.n)), 1e-12 * impact.impulse.norm());
    const Vec<3> l0 = s.b1.angular_momentum() + s.b2.angular_momentum();
    apply(s.b1, s.b2, s.contact, impact.impulse);
    EXPECT_LT((s.b1.angular_momentum() + s.b2.angular_momentum() - l0).norm(), 1e-12 * (1 + l0.norm()));
    const double un = (impact_body(s.b2, s.contact).contact_velocity() - impact_body(s.b1, s.contact).contact_velocity()).dot(s.n);
    EXPECT_NEAR(un, -0.6 * impact.normal_velocity, 1e-12 * std::abs(impact.normal_velocity));
  }
}

TEST(RigidImpulse, SomeTransverseCoefficientsCreateEnergyAndAreReported) {
  // A sideways coefficient on an elastic impact: for some geometries the kinetic energy
  // after exceeds the energy before, which the engine refuses.
  Random rng(15, RandomPurpose::positions);
  int creating = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Collision s = approaching_pair(rng);
    const Impact<3> impact = collision_impulse(impact_body(s.b1, s.contact), impact_body(s.b2, s.contact), s.n, {1.0, 0.0, 3.0});
    if (!(impact.denominator > 0.0) || impact.energy_change > 0.0) ++creating;
  }
  EXPECT_GT(creating, 0);
}

TEST(RigidImpulse, WallIsABodyOfInfiniteMass) {
  // A spinning disc hitting a wall off-centre: elastic, frictionless, energy conserved;
  // the normal contact velocity reverses.
  ImpactBody<2> disc{1.0 / 2.0, InertiaTensor<2>(1.0 / 0.3), Vec<2>(1.0, 0.5), Spin<2>(-4.0), Vec<2>(0.5, 0.3)};
  const ImpactBody<2> wall;
  const Vec<2> n(1.0, 0.0);
  const Impact<2> impact = collision_impulse(disc, wall, n, {});
  ASSERT_TRUE(impact.approaching);
  const double e0 = 0.5 * 2.0 * disc.velocity.squaredNorm() + 0.5 * 0.3 * 16.0;
  const Vec<2> v = disc.velocity + impact.impulse * disc.inverse_mass;
  const double w = disc.angular_velocity[0] + disc.inverse_inertia(0, 0) * cross(disc.lever, impact.impulse)[0];
  EXPECT_NEAR(0.5 * 2.0 * v.squaredNorm() + 0.5 * 0.3 * w * w, e0, 1e-13 * e0);
  const Vec<2> contact_after = v + cross(Spin<2>(w), disc.lever);
  EXPECT_NEAR(contact_after.dot(n), -disc.contact_velocity().dot(n), 1e-13);
}

TEST(RigidCoagulation, StuckBodiesKeepMomentumAndAngularMomentum) {
  Random rng(16, RandomPurpose::positions);
  for (int trial = 0; trial < 100; ++trial) {
    const Body3 a = random_body(rng, Vec<3>(0.1, 0.2, 0.3)), b = random_body(rng, Vec<3>(1.5, -0.4, 0.8));
    const MomentumState<3> j = stuck_together<3>({a.mass, a.centre, a.velocity, a.inertia * a.omega},
                                                 {b.mass, b.centre, b.velocity, b.inertia * b.omega});
    EXPECT_LT((j.mass * j.velocity - a.momentum() - b.momentum()).norm(), 1e-13 * (a.momentum().norm() + b.momentum().norm()));
    const Vec<3> after = j.mass * j.centre.cross(j.velocity) + j.spin_momentum;  // (10)
    const Vec<3> before = a.angular_momentum() + b.angular_momentum();         // (9)
    EXPECT_LT((after - before).norm(), 1e-12 * (1 + before.norm()));
  }
}

TEST(BridgesLaw, IsOneBelowTheCriticalSpeedAndAPowerLawAbove) {
  EXPECT_EQ(bridges_restitution(0.0), 1.0);
  EXPECT_EQ(bridges_restitution(kBridgesCriticalSpeed), 1.0);
  EXPECT_NEAR(bridges_restitution(10 * kBridgesCriticalSpeed), std::pow(10.0, -0.234), 1e-15);
  EXPECT_NEAR(bridges_restitution(1.0), std::pow(1.0 / 0.0077, -0.234), 1e-15);  // 1 cm/s: 0.32
  EXPECT_LT(bridges_restitution(2.0), bridges_restitution(1.0));
}

}  // namespace
}  // namespace ballagg
