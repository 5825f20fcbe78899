// Initial conditions: lattice (paper §4.1), random placement, the velocity laws.
#include <cmath>
#include <array>
#include <numbers>
#include <set>

#include <gtest/gtest.h>

#include "support.hpp"

namespace ballagg {
namespace {

Config defaults() { return Config{}; }

TEST(InitialState, DefaultIsThePapersLatticeWithUnitSpeeds) {
  Config c = defaults();
  c.system.volume_fraction = 0.2;
  const State<2> s = make_initial_state<2>(c);
  ASSERT_EQ(s.n_spheres(), 2500);
  EXPECT_NEAR(s.box.length, std::sqrt(2500 * std::numbers::pi * 0.04 / 0.2), 1e-12);
  // Every sphere sits at the centre of a lattice cell, one per cell.
  const double spacing = s.box.length / 50;
  std::set<std::pair<int, int>> cells;
  for (int i = 0; i < s.n_spheres(); ++i) {
    const Vec<2> x = s.position(i, 0);
    const int cx = static_cast<int>(x[0] / spacing), cy = static_cast<int>(x[1] / spacing);
    EXPECT_NEAR(x[0], (cx + 0.5) * spacing, 1e-12);
    EXPECT_NEAR(x[1], (cy + 0.5) * spacing, 1e-12);
    cells.insert({cx, cy});
    EXPECT_NEAR(s.velocity(i).norm(), 1.0, 1e-15);
  }
  EXPECT_EQ(cells.size(), 2500u);
  EXPECT_EQ(s.n_clusters(), 2500);
}

TEST(InitialState, PartialCubicLatticeFillsCellsInOrder) {
  Config c = defaults();
  c.system.dimension = 3;
  c.system.n = 10;  // a 3x3x3 lattice, first 10 cells
  c.system.volume_fraction = 0.05;
  const State<3> s = make_initial_state<3>(c);
  // The first 10 cells in row-major order (x fastest): the bottom layer and (0, 0, 1).
  const double a = s.box.length / 3;
  std::set<std::array<int, 3>> cells;
  for (int i = 0; i < s.n_spheres(); ++i) {
    const Vec<3> x = s.position(i, 0) / a;
    cells.insert({static_cast<int>(x[0]), static_cast<int>(x[1]), static_cast<int>(x[2])});
  }
  std::set<std::array<int, 3>> expected;
  for (int k = 0; k < 10; ++k) expected.insert({k % 3, (k / 3) % 3, k / 9});
  EXPECT_EQ(cells, expected);
}

TEST(InitialState, RandomPlacementHasNoOverlapAndStaysInsideWalls) {
  for (int d : {2, 3}) {
    Config c = testing::small_config(d, 500, 0.3, Boundary::walls, 4);
    if (d == 2) {
      const State<2> s = make_initial_state<2>(c);
      EXPECT_LT(testing::worst_overlap(s), 0.0);
      for (int i = 0; i < s.n_spheres(); ++i)
        for (int a = 0; a < 2; ++a) {
          EXPECT_GE(s.position(i, 0)[a], 0.5);
          EXPECT_LE(s.position(i, 0)[a], s.box.length - 0.5);
        }
    } else {
      const State<3> s = make_initial_state<3>(c);
      EXPECT_LT(testing::worst_overlap(s), 0.0);
    }
  }
}

TEST(InitialState, UniformVelocitiesLieInTheCubeOfAppendixA) {
  Config c = defaults();
  c.system.n = 10000;
  c.initial.velocities = InitialVelocities::uniform;
  c.initial.speed = 2.0;  // components uniform in [-1, 1]
  const State<2> s = make_initial_state<2>(c);
  double mean = 0.0, square = 0.0;
  for (int i = 0; i < s.n_spheres(); ++i) {
    for (int a = 0; a < 2; ++a) {
      const double v = s.velocity(i)[a];
      EXPECT_GE(v, -1.0);
      EXPECT_LT(v, 1.0);
      mean += v;
      square += v * v;
    }
  }
  mean /= 20000;
  square /= 20000;
  EXPECT_NEAR(mean, 0.0, 0.03);           // 5 sigma for 20000 draws of variance 1/3
  EXPECT_NEAR(square, 1.0 / 3.0, 0.015);
}

// Degond et al. 2023, App. A (Fig. 13) from its example file: spheres of radius 0.2 on a
// lattice of unit spacing in [0, sqrt(N)]^2, velocity components uniform in [-0.5, 0.5].
TEST(InitialState, AppendixAStartIsTheUnitLatticeWithVelocitiesInTheHalfUnitSquare) {
  const std::string file = std::string(BALLAGG_SOURCE_DIR) + "/examples/degond2023/appendix_a_fig13.toml";
  const Config c = load_config(file, {"system.n=2500"});
  const State<2> s = make_initial_state<2>(c);
  ASSERT_EQ(s.n_spheres(), 2500);
  EXPECT_EQ(s.box.length, 50.0);  // sqrt(N) sites of unit spacing
  std::set<std::array<long, 2>> sites;
  for (int i = 0; i < s.n_spheres(); ++i) {
    EXPECT_EQ(s.spheres.radius[i], 0.2);
    std::array<long, 2> site{};
    for (int a = 0; a < 2; ++a) {
      const double x = s.position(i, 0)[a] - 0.5;  // cell centres: 0.5, 1.5, ...
      site[a] = std::lround(x);
      EXPECT_EQ(x, static_cast<double>(site[a])) << "sphere " << i;
      EXPECT_GE(site[a], 0);
      EXPECT_LT(site[a], 50);
    }
    sites.insert(site);
  }
  EXPECT_EQ(sites.size(), 2500u);  // one sphere a site
  // Each component uniform in [-a, a], a = 0.5: mean 0, variance a^2 / 3 = 1/12. Bounds of
  // five standard errors over N = 2500 draws: the mean's sqrt(a^2 / 3 / N), the
  // variance's sqrt(4 a^4 / 45 / N).
  constexpr double kHalfWidth = 0.5, kSigmas = 5.0;
  const double n = s.n_spheres();
  const double mean_bound = kSigmas * std::sqrt(kHalfWidth * kHalfWidth / 3.0 / n);
  const double variance_bound = kSigmas * std::sqrt(4.0 * std::pow(kHalfWidth, 4) / 45.0 / n);
  for (int a = 0; a < 2; ++a) {
    double sum = 0.0, square = 0.0;
    for (int i = 0; i < s.n_spheres(); ++i) {
      const double v = s.velocity(i)[a];
      EXPECT_GE(v, -kHalfWidth);
      EXPECT_LT(v, kHalfWidth);
      sum += v;
      square += v * v;
    }
    const double mean = sum / n, variance = square / n - mean * mean;
    EXPECT_NEAR(mean, 0.0, mean_bound) << "component " << a;
    EXPECT_NEAR(variance, kHalfWidth * kHalfWidth / 3.0, variance_bound) << "component " << a;
  }
}

// The spacing is the key's, whatever the radius: a larger radius keeps the unit lattice.
TEST(InitialState, LatticeSpacingDoesNotDependOnTheRadius) {
  const Config c = parse_config_text("[system]\nn = 9\nradius = 0.45\n[initial]\nlattice_spacing = 1.0\n", "t");
  const State<2> s = make_initial_state<2>(c);
  EXPECT_EQ(s.box.length, 3.0);
  std::set<std::array<double, 2>> sites;
  for (int i = 0; i < s.n_spheres(); ++i) sites.insert({s.position(i, 0)[0], s.position(i, 0)[1]});
  const std::set<std::array<double, 2>> unit{{0.5, 0.5}, {0.5, 1.5}, {0.5, 2.5}, {1.5, 0.5}, {1.5, 1.5},
                                             {1.5, 2.5}, {2.5, 0.5}, {2.5, 1.5}, {2.5, 2.5}};
  EXPECT_EQ(sites, unit);
}

TEST(InitialState, GaussianVelocitiesHaveTheRequestedMeanSquareSpeed) {
  Config c = defaults();
  c.system.dimension = 3;
  c.system.n = 20000;
  c.initial.velocities = InitialVelocities::gaussian;
  c.initial.speed = 1.5;
  const State<3> s = make_initial_state<3>(c);
  double square = 0.0, fourth = 0.0;
  for (int i = 0; i < s.n_spheres(); ++i) {
    const double vx = s.velocity(i)[0];
    square += s.velocity(i).squaredNorm();
    fourth += vx * vx * vx * vx;
  }
  square /= s.n_spheres();
  fourth /= s.n_spheres();
  EXPECT_NEAR(square, 2.25, 0.05);
  // Gaussian kurtosis: <vx^4> = 3 <vx^2>^2 with <vx^2> = 0.75.
  EXPECT_NEAR(fourth, 3 * 0.75 * 0.75, 0.1);
}

TEST(InitialState, FixedSpeedDirectionsAreIsotropic) {
  Config c = defaults();
  c.system.dimension = 3;
  c.system.n = 20000;
  c.system.volume_fraction = 0.1;
  const State<3> s = make_initial_state<3>(c);
  Vec<3> mean = Vec<3>::Zero();
  double zz = 0.0;
  for (int i = 0; i < s.n_spheres(); ++i) {
    EXPECT_NEAR(s.velocity(i).norm(), 1.0, 1e-15);
    mean += s.velocity(i);
    zz += s.velocity(i)[2] * s.velocity(i)[2];
  }
  EXPECT_LT((mean / s.n_spheres()).norm(), 0.03);
  EXPECT_NEAR(zz / s.n_spheres(), 1.0 / 3.0, 0.015);
}

TEST(InitialState, ZeroMomentumRemovesTheCentreOfMassVelocity) {
  Config c = defaults();
  c.system.n = 400;
  c.initial.zero_momentum = true;
  const State<2> s = make_initial_state<2>(c);
  EXPECT_LT(s.momentum().norm(), 1e-12 * s.momentum_scale());
}

TEST(InitialState, VelocitiesDoNotDependOnHowPositionsWereDrawn) {
  Config lattice = testing::small_config(2, 100, 0.2, Boundary::walls, 9);
  lattice.initial.positions = InitialPositions::lattice;
  Config random = lattice;
  random.initial.positions = InitialPositions::random;
  const State<2> a = make_initial_state<2>(lattice), b = make_initial_state<2>(random);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.velocity(i), b.velocity(i));
}

// initial.time: the state's positions are those at that time, and its clock reads it.
TEST(InitialState, InitialTimeStartsTheClockWithThePositionsUnchanged) {
  Config c = defaults();
  c.system.n = 100;
  c.initial.zero_momentum = true;
  const State<2> at_zero = make_initial_state<2>(c);
  c.initial.time = 7.25;
  const State<2> late = make_initial_state<2>(c);
  EXPECT_EQ(late.time, 7.25);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(late.position(i, 7.25), at_zero.position(i, 0.0));
    EXPECT_EQ(late.velocity(i), at_zero.velocity(i));
  }
  for (int k : late.alive_clusters()) EXPECT_EQ(late.clusters[k].anchor_time, 7.25);
}

TEST(InitialState, PlacementErrorsNameTheSetArguments) {
  try {
    make_initial_state<2>(parse_config_text("", "(defaults)", {"system.n=2", "system.volume_fraction=0.5"}));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--set system.n=2 --set system.volume_fraction=0.5: initial.positions = "
                                          "\"lattice\"", 0), 0u) << e.what();
  }
}

TEST(InitialState, LatticeTooDenseIsRefusedWithTheLimit) {
  Config c = defaults();
  c.system.n = 2;  // a 2x2 lattice holds 2 spheres: spacing L/2 must exceed 2R
  c.system.volume_fraction = 0.5;
  try {
    make_initial_state<2>(c);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lattice"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ballagg
