// The time-stepping engine (paper §3): analytic outcomes of simple collisions, conservation
// laws, the stopping conditions of the minimiser after every step, the three cluster
// models, determinism and independence of the thread count.
#include <chrono>
#include <cmath>
#include <functional>
#include <thread>

#include <gtest/gtest.h>

#include "ballagg/core/disjoint_sets.hpp"
#include "ballagg/core/run_guard.hpp"
#include "ballagg/engines/time_stepping/time_step_rule.hpp"
#include "ballagg/engines/time_stepping/time_stepping_engine.hpp"
#include "ballagg/io/state_csv.hpp"
#include "support.hpp"
#include "thread_count.hpp"

namespace ballagg {
namespace {
using testing::Ball;
using testing::make_state;
using testing::Recorder;
using testing::vec;
using testing::worst_overlap;

// The engine's positions and the state's differ in the last bits (wrapped in the box, or
// recomputed from the cluster's origin): relative overlaps computed from the two agree to
// this.
constexpr double kRoundOff = 1e-12;

StopCriteria until(double t, int clusters = 0) {
  StopCriteria s;
  s.clusters = clusters;
  s.time = t;
  return s;
}

template <int D>
RunResult run_ts(State<D>& s, const TimeSteppingSettings& ts, const StopCriteria& stop,
                 RunObserver<D>* observer = nullptr) {
  RunObserver<D> none;
  return make_time_stepping_engine<D>(ts)->run(s, stop, observer ? *observer : none);
}

TimeSteppingSettings settings(TsModel model = TsModel::rigid, double dt_factor = 0.013) {
  TimeSteppingSettings ts;
  ts.model = model;
  ts.daha = default_daha(model);
  ts.dt_factor = dt_factor;
  return ts;
}

template <int D>
double distance(const State<D>& s, int i, int j) {
  return s.box.separation(s.unwrapped_position(i, s.time), s.unwrapped_position(j, s.time)).norm();
}

class TimeStepping : public ::testing::TestWithParam<TsModel> {};
INSTANTIATE_TEST_SUITE_P(Models, TimeStepping,
                         ::testing::Values(TsModel::rigid, TsModel::almost_rigid, TsModel::non_rigid),
                         [](const auto& param_info) {
                           std::string name(to_string(param_info.param));
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST_P(TimeStepping, HeadOnDiscsEndTouchingWithTheMassWeightedVelocity) {
  // Masses 1 and 3 at speeds +1 and -1: the cluster moves at (1 - 3) / 4 = -0.5.
  State<2> s = make_state<2>(10, Boundary::walls,
                             {{vec<2>(3, 5), vec<2>(1, 0), 0.5, 1.0}, {vec<2>(7, 5), vec<2>(-1, 0), 0.5, 3.0}});
  const TimeSteppingSettings ts = settings(GetParam());
  const RunResult r = run_ts(s, ts, until(2.0, 1));
  ASSERT_EQ(s.n_clusters(), 1);
  EXPECT_EQ(r.reason, StopReason::clusters);
  EXPECT_EQ(r.counters.merges, 1);
  EXPECT_NEAR(distance(s, 0, 1), 1.0, ts.daha.eps_c);
  EXPECT_DOUBLE_EQ(s.velocity(0)[0], -0.5);
  EXPECT_DOUBLE_EQ(s.velocity(0)[1], 0.0);
  // The minimiser moves each sphere in inverse proportion to its mass: the centre of mass
  // is where free flight put it, x = (3 + t + 3 (7 - t)) / 4 = 6 - t / 2.
  const double centre = (s.position(0, s.time)[0] + 3.0 * s.position(1, s.time)[0]) / 4.0;
  EXPECT_NEAR(centre, 6.0 - s.time / 2.0, 1e-12);
  EXPECT_NEAR(s.position(0, s.time)[1], 5.0, 1e-12);
}

TEST_P(TimeStepping, ThreeDiscsMeetingAtOnePointFormOneClusterAtRest) {
  // Three discs aimed at the centre at 120 degrees: all three overlap in the same step.
  std::vector<Ball<2>> balls;
  for (int k = 0; k < 3; ++k) {
    const double a = 2.0 * M_PI * k / 3.0;
    const Vec<2> dir = vec<2>(std::cos(a), std::sin(a));
    balls.push_back({vec<2>(10, 10) + 3.0 * dir, -dir, 0.5, 1.0});
  }
  State<2> s = make_state<2>(20, Boundary::walls, balls);
  const TimeSteppingSettings ts = settings(GetParam(), 0.0123);
  const RunResult r = run_ts(s, ts, until(10.0, 1));
  ASSERT_EQ(s.n_clusters(), 1);
  // Pairwise distance sqrt(3) r at distance r from the centre: contact at r = 1 / sqrt(3),
  // t = 3 - 0.577 = 2.42, inside the 10th step of 0.0123 * 20 = 0.246.
  EXPECT_EQ(r.counters.steps, 10);
  EXPECT_LT(s.velocity(0).norm(), 1e-15);
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) EXPECT_GE(distance(s, i, j), 1.0 - ts.daha.eps_c);
  // Each disc touches at least one other: the cluster is connected.
  for (int i = 0; i < 3; ++i)
    EXPECT_LE(std::min(distance(s, i, (i + 1) % 3), distance(s, i, (i + 2) % 3)), 1.0 + 1e-2);
}

// The spheres of every cluster form one connected graph of links, a link being a pair no
// farther apart than `limit` contact distances: a cluster never comes apart.
template <int D>
bool clusters_hold_together(const State<D>& s, double limit) {
  for (int c : s.alive_clusters()) {
    const MemberList& m = s.clusters[c].members;
    DisjointSets sets(static_cast<int>(m.size()));
    int parts = static_cast<int>(m.size());
    for (std::size_t a = 0; a < m.size(); ++a)
      for (std::size_t b = a + 1; b < m.size(); ++b)
        if (distance(s, m[a], m[b]) <= limit * (s.spheres.radius[m[a]] + s.spheres.radius[m[b]]) &&
            sets.find(static_cast<int>(a)) != sets.find(static_cast<int>(b))) {
          sets.unite(static_cast<int>(a), static_cast<int>(b));
          --parts;
        }
    if (parts != 1) return false;
  }
  return true;
}

template <int D>
void expect_invariants_every_step(TsModel model, Boundary boundary, int n, double vf, std::uint64_t seed,
                                  const std::function<void(TimeSteppingSettings&)>& adjust = {}) {
  Config c = testing::small_config(D, n, vf, boundary, seed);
  State<D> s = make_initial_state<D>(c);
  const Vec<D> p0 = s.momentum();
  const double scale = s.momentum_scale();
  const double m0 = s.total_mass();
  TimeSteppingSettings ts = settings(model);
  if (adjust) adjust(ts);
  Recorder<D> rec;
  int clusters = s.n_clusters();
  double worst = -1.0;
  // Rigid clusters keep their links touching; almost-rigid ones within the bond limit. (The
  // non-rigid model lets a cluster rearrange, links included: no such bound.)
  const double link_limit = model == TsModel::rigid ? 1.0 + ts.daha.eps_c
                                                    : (1.0 + ts.bond_stretch) * (1.0 + ts.daha.eps_c);
  bool held = true;
  rec.check = [&](const State<D>& st, const EventRecord&) {
    ASSERT_LE(st.n_clusters(), clusters);
    clusters = st.n_clusters();
    worst = std::max(worst, worst_overlap(st));
    if (model != TsModel::non_rigid && held) held = clusters_hold_together(st, link_limit);
  };
  const RunResult r = run_ts(s, ts, until(1e9, n / 10), &rec);
  EXPECT_EQ(r.reason, StopReason::clusters);
  EXPECT_LE(worst, ts.daha.eps_c) << "overlap left after a step";
  EXPECT_TRUE(held) << "a cluster came apart";
  EXPECT_LE(r.measure("max_residual_overlap"), ts.daha.eps_c);
  // The counter reports overlaps that were there at the end of a step (it is read off the
  // contact checks within the step: an overlap seen before a later round moved it away
  // must not count).
  EXPECT_LE(r.measure("max_residual_overlap"), worst + kRoundOff);
  EXPECT_DOUBLE_EQ(s.total_mass(), m0);
  if (boundary == Boundary::periodic) {
    EXPECT_LE((s.momentum() - p0).norm(), 1e-12 * scale);
  }
}

// Per-sphere models solve larger problems: smaller systems keep the suite fast.
int size_for(TsModel m, int rigid_size) { return m == TsModel::rigid ? rigid_size : rigid_size / 2; }

TEST_P(TimeStepping, Invariants2DWalls) {
  expect_invariants_every_step<2>(GetParam(), Boundary::walls, size_for(GetParam(), 200), 0.2, 3);
}
TEST_P(TimeStepping, Invariants2DPeriodic) {
  expect_invariants_every_step<2>(GetParam(), Boundary::periodic, size_for(GetParam(), 200), 0.3, 4);
}
TEST_P(TimeStepping, Invariants3DWalls) {
  expect_invariants_every_step<3>(GetParam(), Boundary::walls, size_for(GetParam(), 200), 0.2, 5);
}
TEST_P(TimeStepping, Invariants3DPeriodic) {
  expect_invariants_every_step<3>(GetParam(), Boundary::periodic, size_for(GetParam(), 200), 0.2, 6);
}

// The fall-back that keeps the flight, given every group (retreat_pairs = 1: nothing is
// minimised in the rigid model) and long steps (flights of several diameters): the same
// invariants, no overlap left after any step.
void keep_flight_at_long_steps(TimeSteppingSettings& ts) {
  ts.fall_back = TsFallBack::keep_flight;
  ts.retreat_pairs = 1;
  ts.dt_factor = 0.05;
}
TEST(TimeSteppingKeepFlight, Invariants2DWalls) {
  expect_invariants_every_step<2>(TsModel::rigid, Boundary::walls, 400, 0.3, 3, keep_flight_at_long_steps);
}
TEST(TimeSteppingKeepFlight, Invariants2DPeriodic) {
  expect_invariants_every_step<2>(TsModel::rigid, Boundary::periodic, 400, 0.3, 4, keep_flight_at_long_steps);
}
TEST(TimeSteppingKeepFlight, Invariants3DWalls) {
  expect_invariants_every_step<3>(TsModel::rigid, Boundary::walls, 400, 0.2, 5, keep_flight_at_long_steps);
}
TEST(TimeSteppingKeepFlight, Invariants3DPeriodic) {
  expect_invariants_every_step<3>(TsModel::rigid, Boundary::periodic, 400, 0.2, 6, keep_flight_at_long_steps);
}
TEST(TimeSteppingKeepFlight, AlmostRigidInvariants2DWalls) {
  expect_invariants_every_step<2>(TsModel::almost_rigid, Boundary::walls, 100, 0.2, 3, [](TimeSteppingSettings& ts) {
    ts.fall_back = TsFallBack::keep_flight;
    ts.daha.max_iterations = 20;  // most groups to the fall-back
  });
}

// The sweep's searches reuse the pairs an earlier search met while a flight stays within
// ts.sweep_reuse_margin of the flight searched: the same events, so the same run to the
// bit for any margin (0: every search goes to the cell list; 4 radii: nearly every search
// after the first of a flight is a reuse). Long steps of a dense gas, every group to the
// sweep, to one cluster: bodies change their flights hundreds of times.
template <int D>
void expect_the_same_run_for_any_reuse_margin(Boundary boundary, int n, std::uint64_t seed) {
  SCOPED_TRACE(std::to_string(D) + "D " + std::string(to_string(boundary)));
  std::vector<State<D>> finals;
  std::vector<RunResult> results;
  for (const double margin : {0.0, 0.5, 4.0}) {
    State<D> s = make_initial_state<D>(testing::small_config(D, n, 0.3, boundary, seed));
    TimeSteppingSettings ts = settings(TsModel::rigid, 0.05);
    keep_flight_at_long_steps(ts);
    ts.sweep_reuse_margin = margin;
    // The others as long as the first (margin 0) took, and a little more: a run that goes
    // wrong may never reach one cluster.
    const double end = finals.empty() ? 1e9 : 1.5 * finals[0].time;
    results.push_back(run_ts(s, ts, until(end, 1)));
    finals.push_back(std::move(s));
  }
  ASSERT_EQ(results[0].reason, StopReason::clusters);
  for (std::size_t k = 1; k < finals.size(); ++k) {
    EXPECT_EQ(results[k].reason, StopReason::clusters) << "margin " << k;
    EXPECT_EQ(results[k].counters.steps, results[0].counters.steps);
    EXPECT_EQ(results[k].count("placed_at_contact"), results[0].count("placed_at_contact"));
    EXPECT_EQ(finals[k].time, finals[0].time);
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(finals[k].position(i, finals[k].time), finals[0].position(i, finals[0].time)) << "sphere " << i;
      ASSERT_EQ(finals[k].velocity(i), finals[0].velocity(i)) << "sphere " << i;
    }
  }
}
TEST(TimeSteppingKeepFlight, AnySweepReuseMarginGivesTheSameRunToTheBit) {
  expect_the_same_run_for_any_reuse_margin<2>(Boundary::walls, 3000, 1);
  expect_the_same_run_for_any_reuse_margin<2>(Boundary::periodic, 3000, 2);
  expect_the_same_run_for_any_reuse_margin<3>(Boundary::walls, 2000, 3);
}

// Disc A (radius 0.5, speed +1) hits disc B at rest at t = 0.5 within a step; with the
// retreat the pair stops there, with keep-flight it flies on at speed 1/2 (rule (2.9)), and
// when it reaches disc C at rest before the step ends, it stops there and all three join.
struct ThreeDiscsOnALine {
  double x_a, x_b, x_c;
  int clusters;
  double v_a;
};
ThreeDiscsOnALine three_discs_on_a_line(double c_at, double dt, TsFallBack fall_back) {
  State<2> s = make_state<2>(10, Boundary::walls,
                             {{vec<2>(4, 5), vec<2>(1, 0)}, {vec<2>(5.5, 5), vec<2>(0, 0)}, {vec<2>(c_at, 5), vec<2>(0, 0)}});
  TimeSteppingSettings ts = settings(TsModel::rigid, dt / 10);  // L = 10, max |V| = 1
  ts.dt_growth = 1.0;
  ts.retreat_pairs = 1;
  ts.fall_back = fall_back;
  run_ts(s, ts, until(dt));
  return {s.position(0, s.time)[0], s.position(1, s.time)[0], s.position(2, s.time)[0], s.n_clusters(),
          s.velocity(0)[0]};
}

TEST(TimeSteppingKeepFlight, AMergedPairFliesOnToTheEndOfTheStep) {
  const double tolerance = 0.5 * TimeSteppingSettings{}.daha.eps_c;  // the retreat's stop
  // One step of 1.2: A ends it inside B, C (at 7.4) is out of reach.
  const ThreeDiscsOnALine kept = three_discs_on_a_line(7.4, 1.2, TsFallBack::keep_flight);
  EXPECT_EQ(kept.clusters, 2);
  EXPECT_NEAR(kept.x_a, 4.5 + 0.7 * 0.5, tolerance);
  EXPECT_NEAR(kept.x_b, 5.5 + 0.7 * 0.5, tolerance);
  EXPECT_NEAR(kept.v_a, 0.5, 1e-12);
  EXPECT_EQ(kept.x_c, 7.4);
  const ThreeDiscsOnALine retreated = three_discs_on_a_line(7.4, 1.2, TsFallBack::retreat);
  EXPECT_NEAR(retreated.x_a, 4.5, tolerance);
  EXPECT_NEAR(retreated.x_b, 5.5, tolerance);
}

TEST(TimeSteppingKeepFlight, AGroupJoinsAtEachContactAsTheExactDynamicsDo) {
  // C at 6.9 is in the group too (A ends the step inside both B and C). The exact answer:
  // A meets B at t = 0.5 (A at 4.5), the pair (speed 1/2) meets C at t = 1.3, and the
  // three fly on at 1/3 to t = 2; the retreat would leave all three at t = 0.5.
  const double tolerance = 0.5 * TimeSteppingSettings{}.daha.eps_c;
  const ThreeDiscsOnALine kept = three_discs_on_a_line(6.9, 2.0, TsFallBack::keep_flight);
  EXPECT_EQ(kept.clusters, 1);
  EXPECT_NEAR(kept.x_a, 4.5 + 0.8 * 0.5 + 0.7 / 3.0, tolerance);
  EXPECT_NEAR(kept.x_b, 5.5 + 0.8 * 0.5 + 0.7 / 3.0, tolerance);
  EXPECT_NEAR(kept.x_c, 6.9 + 0.7 / 3.0, tolerance);
  EXPECT_NEAR(kept.v_a, 1.0 / 3.0, 1e-12);
}

TEST(TimeSteppingKeepFlight, AFlyingPairStopsAtASphereOutsideItsGroup) {
  const double tolerance = 0.5 * TimeSteppingSettings{}.daha.eps_c;
  // One step of 2: A ends it inside B but not C (at 7.2); the pair reaches C at t = 1.9.
  const ThreeDiscsOnALine kept = three_discs_on_a_line(7.2, 2.0, TsFallBack::keep_flight);
  EXPECT_EQ(kept.clusters, 1);
  EXPECT_NEAR(kept.x_a, 5.2, tolerance);
  EXPECT_NEAR(kept.x_b, 6.2, tolerance);
  EXPECT_EQ(kept.x_c, 7.2);
  EXPECT_NEAR(kept.v_a, 1.0 / 3.0, 1e-12);
}

// The paper's set-up of Table 1 (lattice start, speed 1 in random directions, R = 0.2,
// walls).
template <int D>
State<D> table1_state(int n, double volume_fraction, std::uint64_t seed) {
  Config c = testing::small_config(D, n, volume_fraction, Boundary::walls, seed);
  c.system.radius = 0.2;
  c.initial.positions = InitialPositions::lattice;
  c.initial.velocities = InitialVelocities::fixed_speed;
  return make_initial_state<D>(c);
}

// How deep the deepest sphere is in a wall (0 when none is).
template <int D>
double deepest_in_a_wall(const State<D>& s) {
  double worst = 0.0;
  for (int i = 0; i < s.n_spheres(); ++i)
    for (int a = 0; a < D; ++a) {
      const double x = s.position(i, s.time)[a], r = s.spheres.radius[i];
      worst = std::max({worst, r - x, x + r - s.box.length});
    }
  return worst;
}

// The minimisations see the walls (bounds on the displacements): no sphere is ever pushed
// through one. Without them a 3D run in a small walled box (Vf 0.3, 200 spheres, 7 diameters
// wide) ended with its one cluster wider than the box (61 spheres through a wall, rigid
// model, seed 1; the verify command's box check).
TEST_P(TimeStepping, NoSphereIsPushedThroughAWall) {
  for (std::uint64_t seed : {1, 2}) {
    State<3> s = table1_state<3>(200, 0.3, seed);
    const TimeSteppingSettings ts = settings(GetParam(), 0.005);
    double worst = 0.0;
    Recorder<3> rec;
    rec.check = [&](const State<3>& st, const EventRecord&) { worst = std::max(worst, deepest_in_a_wall(st)); };
    const RunResult r = run_ts(s, ts, until(1e4, 1), &rec);
    EXPECT_EQ(r.reason, StopReason::clusters) << "seed " << seed;
    const double slack = ts.daha.eps_c * 2.0 * 0.2;  // as `ballagg verify`
    EXPECT_LE(worst, slack) << "seed " << seed << " after " << r.counters.steps << " steps";
  }
}

// The non-rigid model's attraction (3.5) acts on where the step's earlier rounds left the
// spheres. It once acted on where they were at the start of the step: every later round
// pushed the spheres a round had moved further the same way, links opened by 100 contact
// distances and spheres ended outside the box (Table 1 set-up, N = 100, Vf = 0.1, seeds 1
// and 2 of the sweep: one of them never reached one cluster).
TEST(TimeSteppingModels, NonRigidClustersStayCompactAndInsideTheWalls) {
  for (std::uint64_t seed : {1, 2}) {
    State<2> s = table1_state<2>(100, 0.1, seed);
    const TimeSteppingSettings ts = settings(TsModel::non_rigid, 0.005);
    double worst = 0.0;
    Recorder<2> rec;
    rec.check = [&](const State<2>& st, const EventRecord&) { worst = std::max(worst, deepest_in_a_wall(st)); };
    const RunResult r = run_ts(s, ts, until(1e4, 1), &rec);
    EXPECT_EQ(r.reason, StopReason::clusters) << "seed " << seed;
    // One diameter of slack: this test is about spheres flung across the box.
    EXPECT_LE(worst, 0.4) << "seed " << seed << ": a sphere left the box";
    // Links open while others close (the model does not keep them), by about one contact
    // distance here; 100 before the fix.
    EXPECT_LT(r.measure("max_link_stretch"), 2.0) << "seed " << seed;
    EXPECT_EQ(s.pinnings(), 0) << "seed " << seed << ": a cluster spanned the box";
  }
}

TEST_P(TimeStepping, SameSeedGivesByteIdenticalStates) {
  auto final_text = [&] {
    State<2> s = make_initial_state<2>(testing::small_config(2, size_for(GetParam(), 300), 0.2, Boundary::periodic, 9));
    run_ts(s, settings(GetParam()), until(1e9, 30));
    return state_csv_text(s);
  };
  EXPECT_EQ(final_text(), final_text());
}

// Independence of the thread count, for every model in 2D and 3D at sizes whose loops run
// on threads: tests/run/test_thread_count.cpp.

TEST(TimeSteppingFiles, FinalStateCanBeFedBackAsTheInitialState) {
  // Clusters left by time stepping overlap internally by up to eps_c, and may touch the
  // walls: the file must still be accepted by a time-stepping run (its own tolerance) and
  // glue the same clusters.
  for (TsModel model : {TsModel::rigid, TsModel::non_rigid}) {
    Config c = testing::small_config(2, 200, 0.3, Boundary::walls, 12);
    State<2> s = make_initial_state<2>(c);
    run_ts(s, settings(model), until(1e9, 20));
    testing::TempDir dir;
    Config again;
    again.engine.kind = EngineKind::ts;
    again.ts = settings(model);
    again.initial.positions = InitialPositions::file;
    again.initial.file = dir.write("state.csv", state_csv_text(s)).string();
    again.system.box_length = s.box.length;
    const State<2> back = make_initial_state<2>(again);
    EXPECT_EQ(back.n_clusters(), s.n_clusters()) << to_string(model);
    EXPECT_EQ(state_csv_text(back), state_csv_text(s)) << to_string(model);
  }
}

TEST(TimeSteppingWalls, ClusterCrossingAWallIsMirroredAndReversed) {
  // One disc at x = 9 moving right at speed 1 in a box of 10 with steps of 1: after the
  // first step its edge is at 10.5, mirrored to 9.5 (centre 9), velocity reversed.
  State<2> s = make_state<2>(10, Boundary::walls, {{vec<2>(9, 5), vec<2>(1, 0)}});
  TimeSteppingSettings ts = settings(TsModel::rigid, 0.1);
  ts.dt_growth = 1.0;
  const RunResult r = run_ts(s, ts, until(1.0));
  EXPECT_EQ(r.counters.wall_bounces, 1);
  EXPECT_NEAR(s.position(0, s.time)[0], 9.0, 1e-12);
  EXPECT_EQ(s.velocity(0), vec<2>(-1, 0));
}

TEST(TimeSteppingSteps, AdaptiveRuleMovesNoClusterMoreThanOneRadius) {
  // (3.3): dt = R_max / max |V| = 0.5 / 2: ten steps to t = 2.5.
  State<2> s = make_state<2>(40, Boundary::periodic, {{vec<2>(5, 5), vec<2>(2, 0)}, {vec<2>(5, 25), vec<2>(0, 1)}});
  TimeSteppingSettings ts = settings(TsModel::rigid, 0.01);
  ts.dt_rule = TsDtRule::adaptive;
  RunResult r = run_ts(s, ts, until(2.5));
  EXPECT_EQ(r.counters.steps, 10);
}

TEST(TimeSteppingSteps, GrowthRuleIsGeometricInTheNumberOfClusters) {
  // 100 discs in a row, touching, speed up to 2: dt(0) = 0.01 * 200 / 2 = 1; the step is
  // dt(0) g^(1 - ln M / ln N): 1 at M = 100, g^(1/2) at M = 10, g at M = 1.
  std::vector<Ball<2>> balls;
  for (int k = 0; k < 100; ++k) balls.push_back({vec<2>(1 + k, 100), vec<2>(k == 0 ? 2 : 0, 0)});
  State<2> s = make_state<2>(200, Boundary::walls, balls);
  TimeSteppingSettings ts = settings(TsModel::rigid, 0.01);
  ts.dt_growth = 4.0;
  const TimeStepRule rule(ts, s);
  EXPECT_DOUBLE_EQ(rule.initial_step(), 1.0);
  EXPECT_DOUBLE_EQ(rule.next(s), 1.0);
  for (int k = 1; k < 100; ++k) {
    s.merge(k - 1, k, 0.0);
    if (s.n_clusters() == 10) {
      EXPECT_NEAR(rule.next(s), 2.0, 1e-12);
    }
  }
  EXPECT_DOUBLE_EQ(rule.next(s), 4.0);
}

TEST(TimeSteppingModels, RigidModelKeepsOldClustersRigid) {
  // A glued chain of six discs hit side-on by three discs: in the rigid model the chain's
  // spheres keep their relative positions exactly (up to round-off).
  std::vector<Ball<2>> balls;
  for (int k = 0; k < 6; ++k) balls.push_back({vec<2>(7.5 + k, 10), vec<2>(0, 0), 0.5, 1.0, 1});
  for (int k = 0; k < 3; ++k) balls.push_back({vec<2>(8.2 + 1.7 * k, 13), vec<2>(0, -1), 0.5, 1.0});
  State<2> s = make_state<2>(20, Boundary::walls, balls);
  const TimeSteppingSettings ts = settings(TsModel::rigid);
  run_ts(s, ts, until(10, 1));
  ASSERT_EQ(s.n_clusters(), 1);
  for (int k = 0; k + 1 < 6; ++k) EXPECT_NEAR(distance(s, k, k + 1), 1.0, 1e-12);
  EXPECT_NEAR(distance(s, 0, 5), 5.0, 1e-12);
  // Each of the three discs touches the chain or another disc.
  for (int i = 6; i < 9; ++i) {
    double nearest = 1e300;
    for (int j = 0; j < 9; ++j)
      if (j != i) nearest = std::min(nearest, distance(s, i, j));
    EXPECT_NEAR(nearest, 1.0, ts.daha.eps_c);
  }
}

TEST(TimeSteppingFallback, UnsolvedPairIsMovedBackToItsContactAlongItsFlight) {
  // Discs of radius 0.5 at x = 4 and 6 approach at speeds +1 and -1 in steps of 0.9: after
  // the first step they overlap by 0.8 of a diameter. With a minimiser that gives up at
  // once, the fall-back moves both back along their flight to where they touched, the
  // event-driven answer: contact at t = 0.5, x = 4.5 and 5.5, then one cluster at rest.
  State<2> s = make_state<2>(10, Boundary::walls, {{vec<2>(4, 5), vec<2>(1, 0)}, {vec<2>(6, 5), vec<2>(-1, 0)}});
  TimeSteppingSettings ts = settings(TsModel::rigid, 0.09);
  ts.dt_growth = 1.0;
  ts.daha.max_iterations = 1;
  const RunResult r = run_ts(s, ts, until(0.9));
  ASSERT_EQ(s.n_clusters(), 1);
  EXPECT_EQ(r.count("placed_at_contact"), 1);
  const double tolerance = 0.5 * ts.daha.eps_c;  // a retreat stops at this overlap
  EXPECT_NEAR(s.position(0, s.time)[0], 4.5, tolerance);
  EXPECT_NEAR(s.position(1, s.time)[0], 5.5, tolerance);
  EXPECT_EQ(s.velocity(0), vec<2>(0, 0));
}

TEST(TimeSteppingFallback, ASphereFlownThroughAnotherIsRetreatedWithoutAMinimisation) {
  // The head-on pair of the test above overlaps by 1 - d / sigma = 0.8 after the first
  // step. With retreat_overlap below that, the group goes to the fall-back at once: no
  // DAHA iteration, and the same event-driven answer. With retreat_overlap above it the
  // minimiser is tried first (and here solves the pair).
  auto run = [](double retreat_overlap) {
    State<2> s = make_state<2>(10, Boundary::walls, {{vec<2>(4, 5), vec<2>(1, 0)}, {vec<2>(6, 5), vec<2>(-1, 0)}});
    TimeSteppingSettings ts = settings(TsModel::rigid, 0.09);
    ts.dt_growth = 1.0;
    ts.retreat_overlap = retreat_overlap;
    const RunResult r = run_ts(s, ts, until(0.9));
    EXPECT_EQ(s.n_clusters(), 1);
    return std::make_pair(r, s.position(0, s.time)[0]);
  };
  const auto [direct, x_direct] = run(0.75);
  EXPECT_EQ(direct.count("placed_at_contact"), 1);
  EXPECT_EQ(direct.count("daha_iterations"), 0);
  EXPECT_NEAR(x_direct, 4.5, 0.5 * TimeSteppingSettings{}.daha.eps_c);
  const auto [tried, x_tried] = run(0.85);
  EXPECT_GT(tried.count("daha_iterations"), 0);
}

TEST(TimeSteppingFallback, GroupsOfManyPairsAreRetreatedWithoutAMinimisation) {
  // retreat_pairs = 1: every group goes to the fall-back, and the run is the event-driven
  // one, step by step: nothing is minimised, every overlap resolved.
  Config c = testing::small_config(2, 300, 0.3, Boundary::walls, 8);
  State<2> s = make_initial_state<2>(c);
  TimeSteppingSettings ts = settings(TsModel::rigid);
  ts.retreat_pairs = 1;
  const RunResult r = run_ts(s, ts, until(1e9, 30));
  EXPECT_EQ(r.count("daha_iterations"), 0);
  EXPECT_EQ(r.count("minimisations"), r.count("placed_at_contact"));
  EXPECT_GT(r.count("placed_at_contact"), 100);
  EXPECT_LE(r.measure("max_residual_overlap"), ts.daha.eps_c);
}

TEST(TimeSteppingFallback, TwoLargeBlocksAreRetreatedToTheirFirstContactOnAnyThreadCount) {
  // Two glued 70 x 70 blocks of touching discs (radius 0.5, 4900 each), the second shifted
  // by half a spacing in y, fly head-on at speeds +1 and -1; their facing columns start 3
  // apart. One step of 1.5 drives them through each other along hundreds of pairs, so the
  // group goes to the fall-back without a minimisation, and the 4900 spheres of the block
  // that searches (the other is the group's largest cluster) are shared among the threads. The event-driven answer: first contact when the facing columns
  // are sqrt(1 - 0.5^2) apart in x, each block having moved (3 - sqrt(0.75)) / 2; then one
  // cluster at rest (equal masses).
  constexpr int kSide = 70;
  std::vector<Ball<2>> balls;
  for (int block = 0; block < 2; ++block)
    for (int a = 0; a < kSide; ++a)
      for (int b = 0; b < kSide; ++b) {
        const Vec<2> x = block == 0 ? vec<2>(10 + a, 20 + b) : vec<2>(10 + kSide + 2 + a, 20.5 + b);
        balls.push_back({x, vec<2>(block == 0 ? 1 : -1, 0), 0.5, 1.0, block});
      }
  const auto [one, two] = testing::on_one_and_two_threads([&] {
    State<2> s = make_state<2>(200, Boundary::walls, balls);
    TimeSteppingSettings ts = settings(TsModel::rigid, 1.5 / 200);  // dt = 1.5
    ts.dt_growth = 1.0;
    const RunResult r = run_ts(s, ts, until(1.5));
    EXPECT_EQ(s.n_clusters(), 1);
    EXPECT_EQ(r.count("placed_at_contact"), 1);
    EXPECT_EQ(r.count("daha_iterations"), 0);
    const double moved = (3.0 - std::sqrt(0.75)) / 2.0;
    const double tolerance = ts.daha.eps_c;  // a retreat stops within eps_c of contact
    EXPECT_NEAR(s.position(0, s.time)[0], 10 + moved, tolerance);
    EXPECT_NEAR(s.position(kSide * kSide, s.time)[0], 10 + kSide + 2 - moved, tolerance);
    EXPECT_EQ(s.velocity(0), vec<2>(0, 0));
    return state_csv_text(s);
  });
  EXPECT_EQ(one, two);
}

// The largest relative overlap between spheres of different clusters.
template <int D>
double worst_overlap_between_clusters(const State<D>& s) {
  double worst = -1.0;
  for (int i = 0; i < s.n_spheres(); ++i)
    for (int j = i + 1; j < s.n_spheres(); ++j)
      if (s.spheres.cluster[i] != s.spheres.cluster[j])
        worst = std::max(worst, 1.0 - distance(s, i, j) / (s.spheres.radius[i] + s.spheres.radius[j]));
  return worst;
}

TEST(TimeSteppingNearPairs, ASphereMeetsADriftingGiantThatWasNotBinnedAgain) {
  // As late in a large run: a giant (a glued 20 x 20 block of touching discs) drifts at
  // 0.12 a step and a lone disc comes at it at 0.2 (dt = 1; the box 40 wide, cells 2 wide).
  // The near list refreshes the disc's pairs from a cell list in which the giant was binned
  // up to 3.7 ago, looking that much wider (StepCells::for_queries): the disc
  // must still stop where it touches the giant, with no overlap left after any step. The
  // event-driven answer: they meet at t = 9.76 / 0.32 = 30.5, the disc touching the middle
  // of the giant's facing column head-on, so the step that ends at t = 31 is the last one.
  // (With the queries looking only as wide as the slack of a freshly binned list, the pair
  // was found two steps late.)
  constexpr int kSide = 20;
  std::vector<Ball<2>> balls;
  for (int a = 0; a < kSide; ++a)
    for (int b = 0; b < kSide; ++b) balls.push_back({vec<2>(5 + a, 10 + b), vec<2>(0.12, 0), 0.5, 1.0, 0});
  balls.push_back({vec<2>(5 + kSide - 1 + 10.76, 19), vec<2>(-0.2, 0), 0.5, 1.0, 1});
  const int disc = kSide * kSide, facing = (kSide - 1) * kSide + 9;  // the giant's sphere at (24, 19)
  State<2> s = make_state<2>(40, Boundary::walls, balls);
  TimeSteppingSettings ts = settings(TsModel::rigid, 0.005);  // dt = 0.005 * 40 / 0.2 = 1
  Recorder<2> rec;
  double worst = -1.0;
  rec.check = [&](const State<2>& st, const EventRecord&) {
    worst = std::max(worst, worst_overlap_between_clusters(st));
  };
  const RunResult r = run_ts(s, ts, until(100.0, 1), &rec);
  EXPECT_EQ(r.reason, StopReason::clusters);
  EXPECT_LE(worst, ts.daha.eps_c) << "overlap left after a step";
  EXPECT_NEAR(distance(s, disc, facing), 1.0, ts.daha.eps_c);
  EXPECT_NEAR(s.position(disc, s.time)[1], 19.0, 1e-9);
  EXPECT_EQ(r.counters.steps, 31);
}

TEST(TimeSteppingLoop, OverlapsLeftWhenTheLoopGivesUpAreSettledByRetreats) {
  // One round per step and long flights: the loop gives up at every step with collisions,
  // its groups retreated one after the other, and some retreats end where others' solutions
  // have moved spheres. Those overlaps are settled (the clusters involved retreat together,
  // with whatever is in their way, until nothing overlaps): after every step no two
  // spheres overlap beyond eps_c, inside a cluster or between two, and the run reaches
  // its 40 clusters. Left alone, such overlaps outlived the step and their groups came back,
  // unsolvable, at every step (the run was short of 40 clusters at t = 200, with clusters
  // overlapping by 0.96); merged where they were (the previous rule), they froze overlaps
  // into the clusters (this test then saw 0.93 inside a cluster, and failed).
  Config c = testing::small_config(2, 400, 0.3, Boundary::walls, 9);
  State<2> s = make_initial_state<2>(c);
  TimeSteppingSettings ts = settings(TsModel::rigid, 0.05);
  ts.max_link_rounds = 1;
  Recorder<2> rec;
  double worst = -1.0;
  rec.check = [&](const State<2>& st, const EventRecord&) { worst = std::max(worst, worst_overlap(st)); };
  const RunResult r = run_ts(s, ts, until(200, 40), &rec);
  EXPECT_EQ(r.reason, StopReason::clusters);
  EXPECT_GT(r.count("link_rounds_exhausted"), 0);
  EXPECT_LE(worst, ts.daha.eps_c);
  EXPECT_LE(r.measure("max_residual_overlap"), ts.daha.eps_c);
}

// Before the first step, waits until the run's wall-clock limit has passed, so that the
// step must end (RunGuard::step_must_end) from its first round on; keeps every sphere's
// position before and after that step.
class WallClockPassesInTheFirstStep final : public RunObserver<2> {
 public:
  WallClockPassesInTheFirstStep(const RunGuard& guard, double limit) : guard_(guard), limit_(limit) {}
  void before_event(const State<2>& s, double) override {
    if (steps_++ > 0) return;
    before = positions(s);
    while (guard_.elapsed() < limit_) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  void after_event(const State<2>& s, const EventRecord&, const EngineCounters&) override {
    if (after.empty()) after = positions(s);
  }
  std::vector<Vec<2>> before, after;

 private:
  static std::vector<Vec<2>> positions(const State<2>& s) {
    std::vector<Vec<2>> x;
    for (int i = 0; i < s.n_spheres(); ++i) x.push_back(s.unwrapped_position(i, s.time));
    return x;
  }
  const RunGuard& guard_;
  double limit_;
  int steps_ = 0;
};

TEST(TimeSteppingLoop, AStepThatMustEndSettlesByReturningEveryClusterToItsStart) {
  // The set-up of the test above, whose first step leaves deep overlaps to settle. The
  // wall-clock limit passes before that step: its settling ends at once, every cluster
  // back where it was at the start of the step (where none overlapped) and no cluster
  // merged, and the run ends after it, with no overlap beyond eps_c.
  Config c = testing::small_config(2, 400, 0.3, Boundary::walls, 9);
  State<2> s = make_initial_state<2>(c);
  TimeSteppingSettings ts = settings(TsModel::rigid, 0.05);
  ts.max_link_rounds = 1;
  // Long enough for the engine's set-up to end before it on a loaded machine (the run
  // would otherwise stop before its first step).
  constexpr double kLimit = 1.0;
  RunGuard guard(kLimit);
  WallClockPassesInTheFirstStep observer(guard, kLimit);
  StopCriteria stop = until(200, 40);
  stop.guard = &guard;
  const int clusters_before = s.n_clusters();
  const RunResult r = run_ts(s, ts, stop, &observer);
  EXPECT_EQ(r.reason, StopReason::wall_seconds);
  EXPECT_EQ(r.counters.steps, 1);
  EXPECT_EQ(s.n_clusters(), clusters_before);
  ASSERT_EQ(observer.after.size(), observer.before.size());
  double farthest = 0.0;
  for (std::size_t i = 0; i < observer.before.size(); ++i)
    farthest = std::max(farthest, (observer.after[i] - observer.before[i]).norm());
  EXPECT_LE(farthest, 1e-12);
  EXPECT_LE(worst_overlap(s), ts.daha.eps_c);

  // Without the limit the same step merges clusters, and they move.
  State<2> free_run = make_initial_state<2>(c);
  const RunResult one_step = run_ts(free_run, ts, until(s.time));
  EXPECT_LT(free_run.n_clusters(), clusters_before);
  EXPECT_EQ(one_step.counters.steps, 1);
}

TEST(TimeSteppingGuards, MinimisationDoesNotPushASphereIntoItsNeighbour) {
  // A fast disc hits a disc at rest from the left; a third disc sits just right of the one
  // at rest, 0.05 away. Pushed apart blindly (the paper's minimisation constrains only S),
  // the struck disc would be driven into the third, and a second round of (3.1)-(3.2) would
  // be needed; the guard stops it at the third disc, which is held where it is, and the
  // step ends in one round without any overlap.
  State<2> s = make_state<2>(20, Boundary::walls,
                             {{vec<2>(7, 10), vec<2>(1, 0)}, {vec<2>(9, 10), vec<2>(0, 0)}, {vec<2>(10.05, 10), vec<2>(0, 0)}});
  TimeSteppingSettings ts = settings(TsModel::rigid, 0.03);  // steps of 0.6: the impact in the second
  ts.dt_growth = 1.0;
  const RunResult r = run_ts(s, ts, until(1.2));
  EXPECT_EQ(r.count("minimisations"), 1);
  EXPECT_EQ(r.count("link_rounds"), 0);
  EXPECT_NE(s.spheres.cluster[0], s.spheres.cluster[2]);
  EXPECT_EQ(s.spheres.cluster[0], s.spheres.cluster[1]);
  EXPECT_NEAR(distance(s, 0, 1), 1.0, ts.daha.eps_c);
  EXPECT_GE(distance(s, 1, 2), 1.0 - ts.daha.eps_c);
  EXPECT_LE(worst_overlap(s), ts.daha.eps_c);
}

}  // namespace
}  // namespace ballagg
