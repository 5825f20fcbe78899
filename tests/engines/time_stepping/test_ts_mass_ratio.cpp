// The time-stepping engine with spheres whose masses differ by hundreds to a thousand times,
// in each cluster model: the run ends in one cluster with every position and velocity
// finite, momentum kept, no overlap beyond eps_c, and the minimisations converging (few
// groups left to the fall-back). docs/time_stepping.md, "Masses".
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/config/config.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/run/simulation.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

// Momentum is conserved to round-off: relative to the sum of the clusters' |momenta|.
constexpr double kMomentumRoundOff = 1e-12;
// Of the rigid model's minimisations, at most this share may be left to the fall-back. With
// the masses in units of each problem's lightest variable it is 0-5 %; with the mean sphere
// as unit the light spheres' minimisations diverge, and 40-50 % of them fall back.
constexpr double kRigidFallBackShare = 0.1;
// These runs end in one cluster by t = 600 or so; a run whose positions turned into NaN
// never does (its clusters no longer meet), and stops here instead.
constexpr double kStopTime = 2000.0;

template <int D>
bool state_is_finite(const State<D>& s) {
  for (int i = 0; i < s.n_spheres(); ++i)
    if (!s.unwrapped_position(i, s.time).allFinite() || !s.velocity(i).allFinite()) return false;
  return true;
}

template <int D>
double heaviest_over_lightest(const State<D>& s) {
  const auto [lightest, heaviest] = std::minmax_element(s.spheres.mass.begin(), s.spheres.mass.end());
  return *heaviest / *lightest;
}

// 120 spheres of the given law in a periodic box at Vf 0.1, run to one cluster.
template <int D>
void expect_one_finite_cluster(const std::string& model, const std::vector<std::string>& law, int seed,
                               double least_mass_ratio) {
  std::vector<std::string> keys{"engine.kind=ts", "ts.model=" + model, "system.dimension=" + std::to_string(D),
                                "system.n=120", "system.volume_fraction=0.1", "system.boundary=periodic",
                                "system.radius=0.5", "system.density=1", "initial.positions=random",
                                "initial.velocities=gaussian", "initial.zero_momentum=true",
                                "initial.seed=" + std::to_string(seed)};
  keys.insert(keys.end(), law.begin(), law.end());
  const Config given = load_config("", keys);
  State<D> s = make_initial_state<D>(given);
  ASSERT_GE(heaviest_over_lightest(s), least_mass_ratio);
  const double scale = s.momentum_scale();
  const Vec<D> momentum = s.momentum();

  const Config c = resolve_defaults<D>(given, s);
  StopCriteria stop;
  stop.clusters = 1;
  stop.time = kStopTime;
  RunObserver<D> none;
  const RunResult r = make_engine<D>(c)->run(s, stop, none);

  const std::string where = std::to_string(D) + "D " + model + " seed " + std::to_string(seed);
  ASSERT_TRUE(state_is_finite(s)) << where;
  ASSERT_EQ(r.reason, StopReason::clusters) << where;
  EXPECT_EQ(s.n_clusters(), 1) << where;
  EXPECT_LE((s.momentum() - momentum).norm(), kMomentumRoundOff * scale) << where;
  EXPECT_LE(testing::worst_overlap(s), c.ts.daha.eps_c) << where;
  if (model == "rigid") {
    EXPECT_LE(r.count("placed_at_contact"), kRigidFallBackShare * r.count("minimisations")) << where;
  }
}

// The lognormal law of examples/polydisperse.toml: drawn radii 0.18 to 1.16 (seed 1), a
// mass ratio of 254 in 3D; in 2D the discs of radii 0.05 and 1.58, a mass ratio of 1000.
const std::vector<std::string> kLognormal{"system.radius_distribution=lognormal", "system.radius_sigma=1.5"};
const std::vector<std::string> kTwoDiscs{"system.radius_distribution=discrete", "system.radii=[0.05,1.5811]"};
const std::vector<std::string> kTwoSpheres{"system.radius_distribution=discrete", "system.radii=[0.1,1.0]"};

class TimeSteppingMassRatio : public ::testing::TestWithParam<std::string> {};

INSTANTIATE_TEST_SUITE_P(Models, TimeSteppingMassRatio, ::testing::Values("rigid", "almost-rigid", "non-rigid"),
                         [](const auto& param_info) {
                           std::string name = param_info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST_P(TimeSteppingMassRatio, LognormalSpheresOfMassRatio250RunToOneFiniteCluster) {
  expect_one_finite_cluster<3>(GetParam(), kLognormal, 1, 250.0);
}

TEST_P(TimeSteppingMassRatio, TwoSizesOfMassRatio1000RunToOneFiniteCluster) {
  expect_one_finite_cluster<2>(GetParam(), kTwoDiscs, 1, 999.0);
  expect_one_finite_cluster<3>(GetParam(), kTwoSpheres, 2, 999.0);
}

}  // namespace
}  // namespace ballagg
