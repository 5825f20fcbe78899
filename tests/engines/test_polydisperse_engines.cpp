// Every engine runs a start of spheres with drawn radii (system.radius_distribution) to half
// as many clusters: the mass and the momentum are kept, no pair overlaps beyond what the
// engine allows, and the spheres keep their drawn radii and masses. Laws of moderate width
// (radii within a factor of about 3); test_ts_mass_ratio.cpp runs ts with wider ones.
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

// Momentum is conserved to round-off: relative to the sum of the spheres' |momenta|.
constexpr double kMomentumRoundOff = 1e-12;
// The event-driven engines' and the rigid-body engine's largest relative overlap after a
// run (round-off of contact times; the rigid-body engine's contact gap, 1e-10).
constexpr double kExactEngineOverlap = 1e-9;

template <int D>
void expect_run_keeps_the_budgets(const std::string& engine, const std::string& law_keys) {
  std::vector<std::string> keys{"engine.kind=" + engine, "system.dimension=" + std::to_string(D), "system.n=120",
                                "system.volume_fraction=0.03", "system.boundary=periodic", "system.radius=0.5",
                                "initial.positions=random", "initial.velocities=gaussian", "initial.zero_momentum=true",
                                "stop.clusters=60"};
  for (std::size_t start = 0, end; start < law_keys.size(); start = end + 1) {
    end = std::min(law_keys.find(' ', start), law_keys.size());
    keys.push_back(law_keys.substr(start, end - start));
  }
  const Config given = load_config("", keys);
  State<D> s = make_initial_state<D>(given);
  const std::vector<double> radii = s.spheres.radius, masses = s.spheres.mass;
  const double mass = s.total_mass();
  const double scale = s.momentum_scale();
  const Vec<D> momentum = s.momentum();

  const Config c = resolve_defaults<D>(given, s);
  StopCriteria stop;
  stop.clusters = 60;
  RunObserver<D> none;
  const RunResult r = make_engine<D>(c)->run(s, stop, none);

  ASSERT_EQ(r.reason, StopReason::clusters) << D << "D";
  EXPECT_EQ(s.n_clusters(), 60);
  EXPECT_EQ(s.spheres.radius, radii);
  EXPECT_EQ(s.spheres.mass, masses);
  EXPECT_NEAR(s.total_mass(), mass, 1e-12 * mass);
  EXPECT_LE((s.momentum() - momentum).norm(), kMomentumRoundOff * scale);
  EXPECT_LE(testing::worst_overlap(s), engine == "ts" ? c.ts.daha.eps_c : kExactEngineOverlap);
}

class PolydisperseEngines : public ::testing::TestWithParam<std::string> {};

INSTANTIATE_TEST_SUITE_P(Engines, PolydisperseEngines, ::testing::Values("ed", "ed-naive", "rigid-body", "ts"),
                         [](const auto& param_info) {
                           std::string name = param_info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST_P(PolydisperseEngines, LognormalRunKeepsMassAndMomentumAndLeavesNoOverlap) {
  const std::string law = "system.radius_distribution=lognormal system.radius_sigma=1.25";
  expect_run_keeps_the_budgets<2>(GetParam(), law);
  expect_run_keeps_the_budgets<3>(GetParam(), law);
}

TEST_P(PolydisperseEngines, DiscreteRunWithADensityKeepsMassAndMomentum) {
  const std::string law = "system.radius_distribution=discrete system.radii=[0.3,0.6] system.radius_weights=[4,1] "
                          "system.density=1";
  expect_run_keeps_the_budgets<2>(GetParam(), law);
  expect_run_keeps_the_budgets<3>(GetParam(), law);
}

}  // namespace
}  // namespace ballagg
