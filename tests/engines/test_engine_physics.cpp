// The physics every engine shares, checked on every engine (ed, ed-naive, rigid-body, ts)
// by one suite: the analytic contact time of two spheres, the analytic times at which a
// sphere hits the walls, sticking at the mass-weighted mean velocity, and a random run
// that keeps mass and momentum and leaves no overlap. The engines differ only in how
// closely they must meet the answers (EngineTolerances): the event-driven engines solve
// every contact exactly, the rigid-body engine advances to within kRigidBodyContactGap of
// it, and ts sees a contact or a wall at the end of the step in which it happened and
// leaves overlaps up to its eps_c (docs/engines.md, docs/time_stepping.md).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/config/config.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/run/simulation.hpp"
#include "support.hpp"

namespace ballagg {
namespace {
using testing::Ball;
using testing::make_state;
using testing::vec;
using testing::worst_overlap;

// Two double results that should be the same number agree to this relative difference
// (4 units in the last place, as EXPECT_DOUBLE_EQ).
constexpr double kRoundOff = 4.0 * std::numeric_limits<double>::epsilon();
// The event-driven engines place touching spheres at their contact distance up to the
// round-off of the positions: relative overlaps within this of zero.
constexpr double kExactContact = 1e-14;
// Largest relative overlap an event-driven run may show after any event (round-off of the
// contact times accumulated over a run).
constexpr double kEventDrivenOverlap = 1e-9;
// The rigid-body engine advances a pair until its gap is below this fraction of the
// contact distance (kContactGap of engines/rigid_body, docs/rigid_body.md): contacts are
// found within it, touching pairs are apart or overlap by at most it.
constexpr double kRigidBodyContactGap = 1e-10;
// Momentum is conserved to round-off: relative to the sum of the bodies' |momenta|.
constexpr double kMomentumRoundOff = 1e-12;

// How closely an engine must meet the analytic answers of a scenario whose spheres of
// contact distance `sigma` approach at `approach_speed` at the fastest speed `max_speed`
// in a box of side `box` (the step of ts follows from these, docs/time_stepping.md).
struct EngineTolerances {
  double early = 0.0;    // how much before the analytic instant a contact or wall hit may be seen
  double late = 0.0;     // ... and how much after it
  double gap = 0.0;      // |1 - d / sigma| of a pair that has just stuck
  double overlap = 0.0;  // largest 1 - d / sigma after any event of a run
};

struct Scale {
  double sigma = 1.0;
  double approach_speed = 1.0;
  double max_speed = 1.0;
  double box = 1.0;
};

// The configuration of an engine, from the keys a user would give.
Config engine_config(const std::string& engine, int dimension, std::vector<std::string> keys = {}) {
  keys.push_back("engine.kind=" + engine);
  keys.push_back("system.dimension=" + std::to_string(dimension));
  return load_config("", keys);
}

EngineTolerances tolerances(const std::string& engine, const Config& c, const Scale& scale) {
  if (engine == "ed" || engine == "ed-naive") return {0.0, 0.0, kExactContact, kEventDrivenOverlap};
  if (engine == "rigid-body") {
    const double t = kRigidBodyContactGap * scale.sigma / scale.approach_speed;
    return {t, t, kRigidBodyContactGap, kRigidBodyContactGap};
  }
  // ts: a contact or a wall crossing is handled at the end of its step, the longest step
  // being dt_growth dt_factor L / max|V_i| (the growth rule); the minimiser leaves pairs
  // touching to eps_c.
  const double longest_step = c.ts.dt_growth * c.ts.dt_factor * scale.box / scale.max_speed;
  return {0.0, longest_step, c.ts.daha.eps_c, c.ts.daha.eps_c};
}

// Seen at `seen` an event that happens at `analytic`: not earlier than `early` before it,
// not later than `late` after it.
void expect_seen_in_time(double seen, double analytic, const EngineTolerances& tol) {
  const double round_off = kRoundOff * std::abs(analytic);
  EXPECT_GE(seen, analytic - tol.early - round_off) << "seen before it happens";
  EXPECT_LE(seen, analytic + tol.late + round_off) << "seen too late";
}

template <int D>
RunResult run(State<D>& s, const Config& c, const StopCriteria& stop, RunObserver<D>& observer) {
  return make_engine<D>(resolve_defaults<D>(c, s))->run(s, stop, observer);
}

// Runs to time t however many clusters remain.
StopCriteria until(double t) {
  StopCriteria s;
  s.clusters = 0;
  s.time = t;
  return s;
}

// Calls `check` after every event, with the state's positions exact at the event's time
// (the rigid-body engine brings a body's positions up to date only for an observer that
// reads them, next_position_read).
template <int D>
class EveryEvent final : public RunObserver<D> {
 public:
  std::function<void(const State<D>&, const EventRecord&)> check;
  std::vector<EventRecord> events;

  double next_position_read() const override { return -std::numeric_limits<double>::infinity(); }
  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters&) override {
    events.push_back(e);
    if (check) check(s, e);
  }
  std::size_t count(EventKind kind) const {
    return static_cast<std::size_t>(std::count_if(events.begin(), events.end(), [&](const EventRecord& e) { return e.kind == kind; }));
  }
};

// After each event: the times at which a cluster count dropped and at which sphere 0's
// velocity along x changed sign.
template <int D>
struct Watch {
  EveryEvent<D> recorder;
  std::vector<double> merges, x_reversals;
  explicit Watch(const State<D>& s) : clusters_(s.n_clusters()), vx_(s.velocity(0)[0]) {
    recorder.check = [this](const State<D>& st, const EventRecord& e) {
      if (st.n_clusters() < clusters_) merges.push_back(e.time);
      clusters_ = st.n_clusters();
      const double vx = st.velocity(0)[0];
      if ((vx < 0) != (vx_ < 0)) x_reversals.push_back(e.time);
      vx_ = vx;
    };
  }

 private:
  int clusters_;
  double vx_;
};

class EnginePhysics : public ::testing::TestWithParam<std::string> {
 protected:
  const std::string& engine() const { return GetParam(); }
};

INSTANTIATE_TEST_SUITE_P(Engines, EnginePhysics, ::testing::Values("ed", "ed-naive", "rigid-body", "ts"),
                         [](const auto& param_info) {
                           std::string name = param_info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST_P(EnginePhysics, SphereHitsTheWallsAtTheAnalyticTimes) {
  // A sphere of radius 0.5 at x = 2 moving at +1 in a box of 10 reaches x = 9.5 at 7.5, is
  // back at x = 0.5 at 16.5, and at 20 is at x = 4 moving at +1 again.
  State<2> s = make_state<2>(10, Boundary::walls, {{vec<2>(2, 5), vec<2>(1, 0)}});
  const Config c = engine_config(engine(), 2);
  const EngineTolerances tol = tolerances(engine(), c, {1.0, 1.0, 1.0, 10.0});
  Watch<2> watch(s);
  const RunResult r = run<2>(s, c, until(20), watch.recorder);
  ASSERT_EQ(watch.x_reversals.size(), 2u);
  // The engines of events turn the sphere at wall events; ts at the end of a step.
  if (engine() != "ts") {
    EXPECT_EQ(watch.recorder.count(EventKind::wall), 2u);
  }
  expect_seen_in_time(watch.x_reversals[0], 7.5, tol);
  expect_seen_in_time(watch.x_reversals[1], 16.5, tol);
  EXPECT_EQ(r.reason, StopReason::time);
  EXPECT_DOUBLE_EQ(s.time, 20.0);
  EXPECT_NEAR(s.position(0, s.time)[0], 4.0, 1e-12);
  EXPECT_EQ(s.velocity(0), vec<2>(1, 0));
}

// Two spheres of masses 1 and 3 meeting at `contact_time` stick and move on at the
// mass-weighted mean velocity `after`, touching.
template <int D>
void expect_sticking(const std::string& engine, State<D> s, double contact_time, const Vec<D>& after) {
  const Config c = engine_config(engine, D);
  const double speed = std::max(s.velocity(0).norm(), s.velocity(1).norm());
  const double approach = (s.velocity(0) - s.velocity(1)).norm();
  const EngineTolerances tol = tolerances(engine, c, {1.0, approach, speed, s.box.length});
  Watch<D> watch(s);
  const RunResult r = run<D>(s, c, {}, watch.recorder);
  ASSERT_EQ(r.reason, StopReason::clusters);
  ASSERT_EQ(s.n_clusters(), 1);
  ASSERT_EQ(watch.merges.size(), 1u);
  if (engine != "ts") {
    EXPECT_EQ(watch.recorder.count(EventKind::collision), 1u);
  }
  expect_seen_in_time(watch.merges[0], contact_time, tol);
  EXPECT_LE((s.velocity(0) - after).norm(), 1e-15);
  EXPECT_LE((s.velocity(1) - after).norm(), 1e-15);
  EXPECT_LE(std::abs(worst_overlap(s)), tol.gap) << "not touching";
}

TEST_P(EnginePhysics, HeadOnPairSticksAtTheAnalyticTimeWithTheMassWeightedVelocity) {
  // Gap 10 - 1 closed at relative speed 2: contact at 4.5; (1 (1, 0.2) + 3 (-1, 0.2)) / 4.
  expect_sticking<3>(engine(),
                     make_state<3>(20, Boundary::walls,
                                   {{vec<3>(5, 10, 10), vec<3>(1, 0.2, 0), 0.5, 1.0},
                                    {vec<3>(15, 10, 10), vec<3>(-1, 0.2, 0), 0.5, 3.0}}),
                     4.5, vec<3>(-0.5, 0.2, 0));
  expect_sticking<2>(engine(),
                     make_state<2>(20, Boundary::walls,
                                   {{vec<2>(5, 10), vec<2>(1, 0.2), 0.5, 1.0}, {vec<2>(15, 10), vec<2>(-1, 0.2), 0.5, 3.0}}),
                     4.5, vec<2>(-0.5, 0.2));
}

TEST_P(EnginePhysics, ObliquePairSticksAtTheAnalyticTimeWithTheMassWeightedVelocity) {
  // Offset 0.6 across the flight: contact when the centres are 0.8 apart along it, after
  // (10 - 0.8) / 2 = 4.6.
  expect_sticking<2>(engine(),
                     make_state<2>(20, Boundary::walls,
                                   {{vec<2>(5, 10), vec<2>(1, 0), 0.5, 1.0}, {vec<2>(15, 10.6), vec<2>(-1, 0), 0.5, 3.0}}),
                     4.6, vec<2>(-0.5, 0));
  expect_sticking<3>(engine(),
                     make_state<3>(20, Boundary::walls,
                                   {{vec<3>(5, 10, 10), vec<3>(1, 0, 0), 0.5, 1.0},
                                    {vec<3>(15, 10.36, 10.48), vec<3>(-1, 0, 0), 0.5, 3.0}}),
                     4.6, vec<3>(-0.5, 0, 0));
}

// A random sticking gas in a periodic box, run until a third of its clusters remain: after
// every event the cluster count has not grown and no pair overlaps beyond the engine's
// tolerance; at the end every sphere is in a cluster, and mass and momentum are those of
// the start.
template <int D>
void expect_conservation(const std::string& engine, int n, std::uint64_t seed) {
  SCOPED_TRACE(std::to_string(D) + "D");
  const Config c = engine_config(engine, D,
                                 {"system.n=" + std::to_string(n), "system.volume_fraction=0.08",
                                  "system.boundary=periodic", "system.radius=0.5", "initial.positions=random",
                                  "initial.velocities=gaussian", "initial.seed=" + std::to_string(seed)});
  State<D> s = make_initial_state<D>(c);
  double max_speed = 0.0;
  for (int i = 0; i < s.n_spheres(); ++i) max_speed = std::max(max_speed, s.velocity(i).norm());
  const EngineTolerances tol = tolerances(engine, c, {1.0, max_speed, max_speed, s.box.length});
  const double mass = s.total_mass();
  const Vec<D> p0 = s.momentum();
  const double scale = s.momentum_scale();
  int clusters = s.n_clusters();
  bool grew = false;
  double worst = -1.0;
  EveryEvent<D> rec;
  rec.check = [&](const State<D>& st, const EventRecord&) {
    grew = grew || st.n_clusters() > clusters;
    clusters = st.n_clusters();
    worst = std::max(worst, worst_overlap(st));
  };
  StopCriteria stop;
  stop.clusters = n / 3;
  const RunResult r = run<D>(s, c, stop, rec);
  ASSERT_EQ(r.reason, StopReason::clusters);
  EXPECT_FALSE(grew) << "a cluster came apart";
  EXPECT_LE(worst, tol.overlap) << "overlap left after an event";
  EXPECT_DOUBLE_EQ(s.total_mass(), mass);
  int members = 0;
  for (int k : s.alive_clusters()) members += static_cast<int>(s.clusters[k].members.size());
  EXPECT_EQ(members, n);
  EXPECT_LE((s.momentum() - p0).norm(), kMomentumRoundOff * scale) << "momentum not conserved";
}

TEST_P(EnginePhysics, RandomPeriodicRunKeepsMassAndMomentumAndLeavesNoOverlap) {
  expect_conservation<2>(engine(), 150, 41);
  expect_conservation<3>(engine(), 150, 42);
}

}  // namespace
}  // namespace ballagg
