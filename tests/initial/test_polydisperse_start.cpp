// Generated starts with radii drawn from system.radius_distribution: no overlaps on the
// lattice or at random, the volume fraction of the sampled spheres, masses ~ R^D or from
// the density, the same state for the same seed on any number of threads, and one error
// when the spheres cannot be placed.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/config/config.hpp"
#include "ballagg/core/state_codec.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "support.hpp"
#include "thread_count.hpp"

namespace ballagg {
namespace {

Config polydisperse(int dimension, const std::string& positions, const std::string& boundary,
                    std::vector<std::string> keys = {}) {
  keys.insert(keys.begin(), {"system.dimension=" + std::to_string(dimension), "system.n=400",
                             "system.volume_fraction=0.06", "system.radius=0.5",
                             "system.radius_distribution=lognormal", "system.radius_sigma=1.5", "system.radius_max=1",
                             "initial.positions=" + positions, "system.boundary=" + boundary});
  return load_config("", keys);
}

template <int D>
State<D> start(const Config& c) {
  return make_initial_state<D>(c);
}

template <int D>
void expect_inside_walls(const State<D>& s) {
  if (s.box.periodic()) return;
  for (int i = 0; i < s.n_spheres(); ++i)
    for (int a = 0; a < D; ++a) {
      EXPECT_GE(s.position(i, 0)[a], s.spheres.radius[i]);
      EXPECT_LE(s.position(i, 0)[a], s.box.length - s.spheres.radius[i]);
    }
}

template <int D>
void expect_valid_start(const Config& c) {
  const State<D> s = start<D>(c);
  ASSERT_EQ(s.n_spheres(), 400);
  EXPECT_LT(testing::worst_overlap(s), 0.0);
  expect_inside_walls(s);
  const auto [lo, hi] = std::minmax_element(s.spheres.radius.begin(), s.spheres.radius.end());
  EXPECT_GT(*hi / *lo, 2.0) << "the radii are drawn, not all equal";
  double volume = 0.0;
  for (double r : s.spheres.radius) volume += sphere_volume(D, r);
  EXPECT_NEAR(volume / std::pow(s.box.length, D), 0.06, 1e-12);
}

TEST(PolydisperseStart, RandomAndLatticeStartsHaveNoOverlapAndTheVolumeFraction) {
  for (const std::string positions : {"random", "lattice"})
    for (const std::string boundary : {"walls", "periodic"}) {
      SCOPED_TRACE(positions + ", " + boundary);
      expect_valid_start<2>(polydisperse(2, positions, boundary));
      expect_valid_start<3>(polydisperse(3, positions, boundary));
    }
}

TEST(PolydisperseStart, TheRadiiAreTheSampledOnes) {
  const Config c = polydisperse(2, "random", "walls");
  std::vector<double> sampled = sample_radii(c.system.radius_distribution, 0.5, 400, c.initial.seed);
  std::vector<double> placed = start<2>(c).spheres.radius;
  std::sort(sampled.begin(), sampled.end());
  std::sort(placed.begin(), placed.end());
  EXPECT_EQ(placed, sampled);
}

TEST(PolydisperseStart, DenseRandomStartsPlaceTheLargestFirst) {
  // A wide power law at a volume fraction that random placement of equal discs reaches
  // only slowly: the large discs go in while the box is empty.
  const Config c = load_config("", {"system.n=600", "system.volume_fraction=0.4", "system.radius_distribution=power-law",
                                    "system.radius_min=0.2", "system.radius_max=2", "system.radius_exponent=3",
                                    "initial.positions=random"});
  const State<2> s = start<2>(c);
  EXPECT_LT(testing::worst_overlap(s), 0.0);
  expect_inside_walls(s);
}

TEST(PolydisperseStart, MassesGoAsRadiusToTheDimensionOrFollowTheDensity) {
  const State<3> s = start<3>(polydisperse(3, "random", "walls", {"system.mass=2"}));
  for (int i = 0; i < s.n_spheres(); ++i)
    EXPECT_NEAR(s.spheres.mass[i], 2.0 * std::pow(s.spheres.radius[i] / 0.5, 3), 1e-14 * s.spheres.mass[i]);
  const State<2> d = start<2>(polydisperse(2, "lattice", "walls", {"system.density=4"}));
  for (int i = 0; i < d.n_spheres(); ++i)
    EXPECT_NEAR(d.spheres.mass[i], 4.0 * std::numbers::pi * std::pow(d.spheres.radius[i], 2), 1e-14 * d.spheres.mass[i]);
  // One radius with a density: every sphere density * pi R^2.
  const State<2> one = start<2>(load_config("", {"system.n=9", "system.density=2"}));
  for (double m : one.spheres.mass) EXPECT_DOUBLE_EQ(m, 2.0 * std::numbers::pi * 0.04);
}

TEST(PolydisperseStart, SameSeedGivesTheSameStateOnOneThreadAndOnTwo) {
  const Config c = polydisperse(3, "random", "periodic");
  const auto [one, two] = testing::on_one_and_two_threads([&] { return StateCodec<3>::encode(start<3>(c)); });
  EXPECT_EQ(one, two);
  Config other = c;
  other.initial.seed = 2;
  EXPECT_NE(StateCodec<3>::encode(start<3>(other)), one);
}

TEST(PolydisperseStart, ALatticeTooFineForTheLargestSphereIsRefused) {
  const Config c = load_config("", {"system.n=400", "system.volume_fraction=0.4", "system.radius_distribution=uniform",
                                    "system.radius_min=0.1", "system.radius_max=1"});
  try {
    start<2>(c);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_PRED_FORMAT2(::testing::IsSubstring, "is not larger than the largest sampled diameter", e.what());
  }
}

TEST(PolydisperseStart, AVolumeFractionRandomPlacementCannotReachIsOneError) {
  const Config c = load_config("", {"system.n=300", "system.volume_fraction=0.7", "system.radius_distribution=uniform",
                                    "system.radius_min=0.4", "system.radius_max=0.5", "initial.positions=random"});
  try {
    start<2>(c);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_PRED_FORMAT2(::testing::IsSubstring, "found no free place in 100000 tries", e.what());
  }
}

}  // namespace
}  // namespace ballagg
