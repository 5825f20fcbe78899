// Torque-free rotation (Richardson 1995 eqs. 5-6) by the exact propagator: it conserves the
// space-frame angular momentum and the rotational energy however long a body flies, and its
// orientation agrees with an independent Runge-Kutta integration of dR/dt = [omega]x R.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "ballagg/core/inertia.hpp"
#include "ballagg/core/random.hpp"
#include "ballagg/engines/rigid_body/free_rotation.hpp"
#include "ballagg/engines/rigid_body/rigid_bodies.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

Rotation<3> skew(const Vec<3>& w) {
  Rotation<3> s;
  s << 0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0;
  return s;
}

// Reference: classical RK4 on the rotation matrix with omega = R I^-1 R^T h (h constant).
Rotation<3> runge_kutta_orientation(Rotation<3> r, const Vec<3>& moments, const Vec<3>& h, double duration, int steps) {
  auto rate = [&](const Rotation<3>& q) {
    const Vec<3> w = q * (q.transpose() * h).cwiseQuotient(moments);
    return Rotation<3>(skew(w) * q);
  };
  const double dt = duration / steps;
  for (int k = 0; k < steps; ++k) {
    const Rotation<3> k1 = rate(r), k2 = rate(r + 0.5 * dt * k1), k3 = rate(r + 0.5 * dt * k2), k4 = rate(r + dt * k3);
    r += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return r;
}

// Space-frame angular momentum from a pose: R I R^T omega.
Vec<3> momentum_of(const FreeRotation<3>::Pose& p, const Vec<3>& moments) {
  return p.rotation * moments.asDiagonal() * p.rotation.transpose() * p.angular_velocity;
}

struct Case {
  const char* name;
  Vec<3> moments;
  Vec<3> h;
};

// Asymmetric bodies circling either axis, the separatrix, symmetric tops (a dimer spinning
// end over end with a round-off component along its axis), a sphere, and rest.
const Case kCases[] = {
    {"asymmetric, round the largest axis", {1.0, 2.0, 3.5}, {0.7, -1.3, 2.1}},
    {"asymmetric, round the smallest axis", {3.5, 2.0, 1.0}, {0.7, -1.3, 2.1}},
    {"near the separatrix", {1.0, 2.0, 3.0}, {1e-9, 1.0, 1e-9}},
    {"prolate symmetric top (dimer) spinning end over end", {0.008, 0.028, 0.028}, {1e-17, 0.58, 0.25}},
    {"nearly symmetric, slow nutation", {0.008, 0.028, 0.02800001}, {1e-9, 0.58, 0.25}},
    {"oblate symmetric top", {2.0, 2.0, 1.0}, {0.4, 0.1, 3.0}},
    {"about a principal axis", {1.0, 2.0, 3.0}, {0.0, 0.0, 2.0}},
    {"sphere", {0.4, 0.4, 0.4}, {1.0, -2.0, 0.5}},
    {"at rest", {1.0, 2.0, 3.0}, {0.0, 0.0, 0.0}},
};

TEST(FreeRotation, OrientationAgreesWithRungeKuttaIntegration) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3, Vec<3>(1, 2, 3).normalized()));
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.name);
    const double t0 = 0.5;
    const FreeRotation<3> f(c.moments, q, c.h, t0);
    const double speed = std::max(f.max_angular_speed(), 1e-3);
    const double duration = 3.0 * 2.0 * std::numbers::pi / speed;  // a few turns
    const Rotation<3> reference = runge_kutta_orientation(q.toRotationMatrix(), c.moments, c.h, duration, 60000);
    const FreeRotation<3>::Pose p = f.at(t0 + duration);
    EXPECT_LT((p.rotation - reference).norm(), 1e-8);
    const Vec<3> w = reference * (reference.transpose() * c.h).cwiseQuotient(c.moments);
    EXPECT_LT((p.angular_velocity - w).norm(), 1e-8 * std::max(1.0, w.norm()));
    EXPECT_LT((p.rotation * p.rotation.transpose() - Rotation<3>::Identity()).norm(), 1e-14);
  }
}

TEST(FreeRotation, AsymmetricAggregateKeepsAngularMomentumAndEnergyOver1e4Periods) {
  // A five-sphere aggregate (three distinct principal moments) with a random spin.
  using testing::Ball;
  using testing::vec;
  std::vector<Ball<3>> balls;
  for (const Vec<3>& x : {vec<3>(5, 5, 5), vec<3>(5.2, 5, 5), vec<3>(5.2, 5.2, 5), vec<3>(5.4, 5.2, 5), vec<3>(5.4, 5.2, 5.2)})
    balls.push_back({x, Vec<3>::Zero(), 0.1, 1.0, 0});
  State<3> s = testing::make_state<3>(20.0, Boundary::walls, balls);
  s.spin.assign(s.clusters.size(), {});
  s.spin[0].angular_velocity = Vec<3>(3.0, -7.0, 11.0);
  RigidBodies<3> bodies;
  bodies.build(s);
  const auto& body = bodies[0];
  const Vec<3> moments = body.rotation.moments();
  EXPECT_GT(moments.maxCoeff() - moments.minCoeff(), 0.1 * moments.maxCoeff());
  const Vec<3> h0 = body.rotation.angular_momentum();
  const double e0 = body.rotation.energy();
  const double period = 2.0 * std::numbers::pi / body.rotation.max_angular_speed();
  Random rng(7, RandomPurpose::positions);
  double worst_momentum = 0.0, worst_energy = 0.0;
  for (int k = 0; k <= 200; ++k) {
    const double t = k == 200 ? 1e4 * period : rng.uniform(0.0, 1e4 * period);
    const auto p = body.rotation.at(t);
    // In the own frame: L = R I_own R^T omega with I_own the inertia about the centre.
    const Vec<3> h = p.rotation * body.inertia * p.rotation.transpose() * p.angular_velocity;
    worst_momentum = std::max(worst_momentum, (h - h0).norm() / h0.norm());
    worst_energy = std::max(worst_energy, std::abs(0.5 * p.angular_velocity.dot(h) - e0) / e0);
  }
  EXPECT_LT(worst_momentum, 1e-9);
  EXPECT_LT(worst_energy, 1e-9);
  // The same invariants from the principal-frame propagator alone.
  const FreeRotation<3> f(Vec<3>(1.0, 2.0, 3.5), Eigen::Quaterniond::Identity(), Vec<3>(0.7, -1.3, 2.1), 0.0);
  const auto far = f.at(1e4 * 2.0 * std::numbers::pi / f.max_angular_speed());
  EXPECT_LT((momentum_of(far, Vec<3>(1.0, 2.0, 3.5)) - f.angular_momentum()).norm() / f.angular_momentum().norm(), 1e-9);
}

TEST(FreeRotation, SpinNeverExceedsItsBounds) {
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.name);
    const FreeRotation<3> f(c.moments, Eigen::Quaterniond::Identity(), c.h, 0.0);
    double fastest = 0.0, sharpest = 0.0;
    for (int k = 0; k < 2000; ++k) {
      const double t = 0.01 * k, h = 1e-6;
      const Vec<3> w = f.at(t).angular_velocity;
      fastest = std::max(fastest, w.norm());
      sharpest = std::max(sharpest, (f.at(t + h).angular_velocity - f.at(t - h).angular_velocity).norm() / (2 * h));
    }
    EXPECT_LE(fastest, f.max_angular_speed() * (1 + 1e-12));
    EXPECT_LE(sharpest, f.max_angular_acceleration() * (1 + 1e-6) + 1e-6);
  }
}

TEST(FreeRotation, TwoDimensionalSpinIsConstantAndTheAngleLinear) {
  const FreeRotation<2> f(0.5, 0.25, Spin<2>(2.0), 1.0);
  EXPECT_EQ(f.at(3.0).angular_velocity[0], 4.0);
  EXPECT_DOUBLE_EQ(f.angle_at(3.0), 0.25 + 4.0 * 2.0);
  EXPECT_LT((f.rotation_at(3.0) - plane_rotation(8.25)).norm(), 1e-15);
  EXPECT_DOUBLE_EQ(f.energy(), 0.5 * 2.0 * 4.0);
}

TEST(Inertia, DimerHasTheMomentsOfEquation1) {
  // Two touching spheres (m, R): about the axis 2 x 2/5 m R^2, across it that plus 2 m R^2.
  const std::vector<Vec<3>> x{Vec<3>(0, 0, 0), Vec<3>(2, 0, 0)};
  const std::vector<double> r{1.0, 1.0}, m{1.0, 1.0};
  const MassProperties<3> p = sphere_mass_properties<3>(x, r, m);
  EXPECT_DOUBLE_EQ(p.mass, 2.0);
  EXPECT_EQ(p.centre, Vec<3>(1, 0, 0));
  const PrincipalAxes<3> axes = principal_axes(p.inertia);
  EXPECT_NEAR(axes.moments[0], 0.8, 1e-14);
  EXPECT_NEAR(axes.moments[1], 2.8, 1e-14);
  EXPECT_NEAR(axes.moments[2], 2.8, 1e-14);
  EXPECT_NEAR(axes.axes.determinant(), 1.0, 1e-14);
  EXPECT_NEAR(std::abs(axes.axes.col(0).dot(Vec<3>::UnitX())), 1.0, 1e-14);
  // Discs: 1/2 m R^2 each plus m |r|^2.
  const std::vector<Vec<2>> y{Vec<2>(0, 0), Vec<2>(2, 0)};
  EXPECT_NEAR(sphere_mass_properties<2>(y, r, m).inertia(0, 0), 1.0 + 2.0, 1e-14);
}

TEST(Inertia, ParallelAxisCombinationEqualsTheDirectSum) {
  Random rng(3, RandomPurpose::positions);
  std::vector<Vec<3>> x(7);
  std::vector<double> r(7), m(7);
  for (int k = 0; k < 7; ++k) {
    x[k] = Vec<3>(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
    r[k] = rng.uniform(0.1, 0.5);
    m[k] = rng.uniform(0.5, 2.0);
  }
  const MassProperties<3> all = sphere_mass_properties<3>(x, r, m);
  const auto first = sphere_mass_properties<3>(std::span(x).first(3), std::span(r).first(3), std::span(m).first(3));
  const auto rest = sphere_mass_properties<3>(std::span(x).last(4), std::span(r).last(4), std::span(m).last(4));
  const MassProperties<3> joined = combined(first, rest);
  EXPECT_NEAR(joined.mass, all.mass, 1e-14);
  EXPECT_LT((joined.centre - all.centre).norm(), 1e-14);
  EXPECT_LT((joined.inertia - all.inertia).norm(), 1e-13 * all.inertia.norm());
}

}  // namespace
}  // namespace ballagg
