// The event-driven engines against analytic answers and conservation laws. Every test body
// runs on both the fast engine (`ed`) and the paper's O(N^2) reference (`ed-naive`). The
// analytic wall and contact times that every engine meets: tests/engines/test_engine_physics.cpp.
#include <chrono>
#include <cmath>
#include <csignal>
#include <stdexcept>

#include <gtest/gtest.h>

#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/io/state_csv.hpp"
#include "support.hpp"

namespace ballagg {
namespace {
using testing::Ball;
using testing::make_state;
using testing::Recorder;
using testing::run_engine;
using testing::vec;
using testing::worst_overlap;

class EventDriven : public ::testing::TestWithParam<std::string> {
 protected:
  std::string engine() const { return GetParam(); }
};

INSTANTIATE_TEST_SUITE_P(Engines, EventDriven, ::testing::Values("ed", "ed-naive"),
                         [](const auto& param_info) { return param_info.param == "ed" ? std::string("ed") : std::string("naive"); });

// Runs to time t however many clusters remain (a single cluster would otherwise stop the
// run at once: the default stop.clusters is 1).
StopCriteria until(double t) {
  StopCriteria s;
  s.clusters = 0;
  s.time = t;
  return s;
}

TEST_P(EventDriven, GluedClusterReflectsWhenItsOuterSphereTouchesTheWall) {
  // A 2-sphere cluster moving up: the upper sphere (y = 7, radius 0.5) reaches y = 9.5 at
  // t = 2.5 / 0.5 = 5 and the whole cluster turns back.
  State<2> s = make_state<2>(10, Boundary::walls,
                             {{vec<2>(4, 6), vec<2>(0, 0.5), 0.5, 1.0, 3}, {vec<2>(4, 7), vec<2>(0, 0.5), 0.5, 1.0, 3}});
  Recorder<2> rec;
  run_engine(s, engine(), {}, until(6), &rec);
  const auto walls = rec.of_kind(EventKind::wall);
  ASSERT_EQ(walls.size(), 1u);
  EXPECT_DOUBLE_EQ(walls[0].time, 5.0);
  EXPECT_EQ(walls[0].axis, 1);
  EXPECT_EQ(s.velocity(0), vec<2>(0, -0.5));
  EXPECT_EQ(s.velocity(1), vec<2>(0, -0.5));
  EXPECT_NEAR(s.position(1, s.time)[1], 9.0, 1e-12);
}

TEST_P(EventDriven, BounceReversesTheApproachTimesRestitution) {
  State<2> s = make_state<2>(20, Boundary::walls,
                             {{vec<2>(5, 10), vec<2>(1, 0)}, {vec<2>(15, 10), vec<2>(-1, 0)}});
  run_engine(s, engine(), {CollisionOutcome::bounce, 0.5, 0.0}, until(5), nullptr);
  EXPECT_NEAR((s.velocity(0) - vec<2>(-0.5, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((s.velocity(1) - vec<2>(0.5, 0)).norm(), 0.0, 1e-15);
  EXPECT_EQ(s.n_clusters(), 2);
}

TEST_P(EventDriven, ZeroRestitutionBounceHappensOnceAndThePairSlidesApart) {
  // After a perfectly inelastic bounce the normal relative velocity is zero up to
  // round-off: the touching pair must not be predicted to collide again and again.
  State<2> s = make_state<2>(20, Boundary::walls, {{vec<2>(5, 10), vec<2>(1, 0)}, {vec<2>(15, 10.5), vec<2>(-1, 0)}});
  Recorder<2> rec;
  double normal_velocity_after = 1.0;
  rec.check = [&](const State<2>& st, const EventRecord& e) {
    if (e.kind != EventKind::collision) return;
    const Vec<2> n = (st.position(0, st.time) - st.position(1, st.time)).normalized();
    normal_velocity_after = (st.velocity(0) - st.velocity(1)).dot(n);
  };
  run_engine(s, engine(), {CollisionOutcome::bounce, 0.0, 0.0}, until(6), &rec);
  EXPECT_EQ(rec.of_kind(EventKind::collision).size(), 1u);
  EXPECT_NEAR(normal_velocity_after, 0.0, 1e-15);
  EXPECT_LE(worst_overlap(s), 1e-12);
  EXPECT_GT(-worst_overlap(s), 0.1);  // slid apart
}

TEST_P(EventDriven, SymmetricThreeBodyCollisionMergesAllAtOnce) {
  // A and C hit the resting B from both sides at the same instant t = 1: the contact
  // cascade glues all three, conserving momentum, whatever order the two contacts take.
  State<2> s = make_state<2>(20, Boundary::walls,
                             {{vec<2>(8, 10), vec<2>(1, 0.5)}, {vec<2>(10, 10), vec<2>(0, 0.5)}, {vec<2>(12, 10), vec<2>(-1, 0.5)}});
  Recorder<2> rec;
  const RunResult r = run_engine(s, engine(), {}, {}, &rec);
  ASSERT_EQ(r.reason, StopReason::clusters);
  ASSERT_EQ(rec.of_kind(EventKind::collision).size(), 1u);
  EXPECT_EQ(rec.of_kind(EventKind::collision)[0].merges, 2);
  EXPECT_DOUBLE_EQ(rec.of_kind(EventKind::collision)[0].time, 1.0);
  EXPECT_NEAR((s.velocity(0) - vec<2>(0, 0.5)).norm(), 0.0, 1e-15);
}

TEST_P(EventDriven, ClusterStraddlingAPeriodicFaceCollidesAcrossIt) {
  // A glued pair sits across x = 0 (spheres at x = 9.5 and x = 0.5); a sphere at x = 5
  // moving left meets the sphere at x = 0.5 when the gap of 3.5 has closed: t = 3.5.
  State<2> s = make_state<2>(10, Boundary::periodic,
                             {{vec<2>(9.5, 5), vec<2>(0, 0), 0.5, 1.0, 1}, {vec<2>(0.5, 5), vec<2>(0, 0), 0.5, 1.0, 1},
                              {vec<2>(5, 5), vec<2>(-1, 0)}});
  ASSERT_EQ(s.n_clusters(), 2);
  Recorder<2> rec;
  run_engine(s, engine(), {}, {}, &rec);
  ASSERT_EQ(rec.of_kind(EventKind::collision).size(), 1u);
  const EventRecord hit = rec.of_kind(EventKind::collision)[0];
  EXPECT_DOUBLE_EQ(hit.time, 3.5);
  EXPECT_EQ(hit.sphere_i, 1);
  EXPECT_EQ(hit.sphere_j, 2);
  EXPECT_NEAR(worst_overlap(s), 0.0, 1e-14);
}

TEST_P(EventDriven, PeriodicPairMeetsThroughTheImageItApproaches) {
  // At t = 0 the nearest image of B (x = 7.5) seen from A (x = 1) is at x = -2.5, behind
  // A; A moves away from it and towards B's direct image: they touch at t = 5.5.
  State<2> s = make_state<2>(10, Boundary::periodic, {{vec<2>(1, 5), vec<2>(1, 0)}, {vec<2>(7.5, 5), vec<2>(0, 0)}});
  Recorder<2> rec;
  run_engine(s, engine(), {}, {}, &rec);
  ASSERT_EQ(rec.of_kind(EventKind::collision).size(), 1u);
  EXPECT_DOUBLE_EQ(rec.of_kind(EventKind::collision)[0].time, 5.5);
}

TEST_P(EventDriven, PeriodicPairMeetsAfterWrappingAroundTheBoxSeveralTimes) {
  // A crosses the box 3 times before its trajectory meets B: dx = 0, dy = 2.9 per lap;
  // contact needs the y offset within 1 of B. Lap k puts A at y = 0.5 + 2.9 k (mod 10):
  // 0.5, 3.4, 6.3, 9.2 -> B at y = 9.5 is within 1 in lap 3.
  State<2> s = make_state<2>(10, Boundary::periodic, {{vec<2>(1, 0.5), vec<2>(10, 2.9)}, {vec<2>(5, 9.5), vec<2>(0, 0)}});
  Recorder<2> rec;
  run_engine(s, engine(), {}, until(10), &rec);
  ASSERT_GE(rec.of_kind(EventKind::collision).size(), 1u);
  const double t = rec.of_kind(EventKind::collision)[0].time;
  EXPECT_GT(t, 3.0);
  EXPECT_LT(t, 4.0);
  EXPECT_LE(worst_overlap(s), 1e-12);
}

TEST_P(EventDriven, ClusterNearlyAsWideAsTheBoxRattlesWithoutStalling) {
  // A rod 1e-6 narrower than the box bounces between the walls every 1e-6 / 0.5 time
  // units: many events, but each is exact and the run reaches its stop time.
  std::vector<Ball<2>> rod;
  for (int k = 0; k < 4; ++k) rod.push_back({vec<2>(0.5 + k, 2), vec<2>(0.5, 0.25), 0.5, 1.0, 1});
  State<2> s = make_state<2>(4 + 1e-6, Boundary::walls, rod);
  Recorder<2> rec;
  const RunResult r = run_engine(s, engine(), {}, until(0.01), &rec);
  EXPECT_EQ(r.reason, StopReason::time);
  EXPECT_GT(r.counters.wall_bounces, 4000);
  EXPECT_LT(r.counters.wall_bounces, 5100);
  const double left = s.origin(0, s.time)[0] + s.extent(0).lo[0];
  const double right = s.origin(0, s.time)[0] + s.extent(0).hi[0];
  EXPECT_GE(left, -1e-12);
  EXPECT_LE(right, s.box.length + 1e-12);
}

TEST_P(EventDriven, ClusterSpanningTheBoxIsPinnedInsteadOfBouncingForever) {
  // A rod exactly as wide as the box would need infinitely many bounces; it is pinned
  // along x and keeps moving along y.
  std::vector<Ball<2>> rod;
  for (int k = 0; k < 4; ++k) rod.push_back({vec<2>(0.5 + k, 2), vec<2>(0.5, 0.25), 0.5, 1.0, 1});
  State<2> s = make_state<2>(4, Boundary::walls, rod);
  Recorder<2> rec;
  const RunResult r = run_engine(s, engine(), {}, until(10), &rec);
  EXPECT_EQ(r.reason, StopReason::time);
  EXPECT_EQ(s.velocity(0)[0], 0.0);
  EXPECT_EQ(std::abs(s.velocity(0)[1]), 0.25);
  EXPECT_LE(r.counters.wall_bounces, 2);
}

TEST_P(EventDriven, SphereStickingToAClusterTouchingOneWallSpansTheBoxAndIsPinned) {
  // The 3-sphere rod touches x = 0; a fourth sphere arriving along x completes a rod of
  // width L: the merged cluster must be pinned, not bounce forever.
  std::vector<Ball<2>> balls;
  for (int k = 0; k < 3; ++k) balls.push_back({vec<2>(0.5 + k, 2), vec<2>(0, 0), 0.5, 1.0, 1});
  balls.push_back({vec<2>(3.5, 2), vec<2>(-1, 0), 0.5, 1.0});
  State<2> s = make_state<2>(4, Boundary::walls, balls);
  const RunResult r = run_engine(s, engine(), {}, until(5), nullptr);
  EXPECT_EQ(s.n_clusters(), 1);
  EXPECT_EQ(s.velocity(0)[0], 0.0);
  EXPECT_LE(r.counters.wall_bounces, 2);
}

TEST_P(EventDriven, InelasticCollapseIsStoppedByTheTcModel) {
  // A light sphere between two heavy ones with restitution 0.1 collides infinitely often
  // in a finite time (inelastic collapse): without the TC model the run stalls at that
  // instant; with it the run finishes.
  const std::vector<testing::Ball<2>> balls{{vec<2>(10, 20), vec<2>(1, 0), 0.5, 50.0},
                                            {vec<2>(20, 20), vec<2>(0, 0), 0.5, 1.0},
                                            {vec<2>(30, 20), vec<2>(-1, 0), 0.5, 50.0}};
  State<2> stalls = make_state<2>(40, Boundary::walls, balls);
  StopCriteria limited = until(30);
  limited.wall_seconds = 0.2;
  EXPECT_EQ(run_engine(stalls, engine(), {CollisionOutcome::bounce, 0.1, 0.0}, limited, nullptr).reason,
            StopReason::wall_seconds);
  EXPECT_LT(stalls.time, 10.0);

  State<2> s = make_state<2>(40, Boundary::walls, balls);
  const RunResult r = run_engine(s, engine(), {CollisionOutcome::bounce, 0.1, 1e-9}, limited, nullptr);
  EXPECT_EQ(r.reason, StopReason::time);
  EXPECT_LT(r.counters.collisions, 100000);
  EXPECT_LE(worst_overlap(s), 1e-9);
}

TEST_P(EventDriven, StopsAtTheRequestedNumberOfClusters) {
  Config c = testing::small_config(2, 120, 0.2, Boundary::walls, 3);
  State<2> s = make_initial_state<2>(c);
  StopCriteria stop;
  stop.clusters = 40;
  Recorder<2> rec;
  const RunResult r = run_engine(s, engine(), {}, stop, &rec);
  EXPECT_EQ(r.reason, StopReason::clusters);
  EXPECT_LE(s.n_clusters(), 40);
  EXPECT_GT(s.n_clusters() + rec.events.back().merges, 40);
}

// Counts the events handled after `limit` wall seconds from the start of the run.
class EventsPastAWallClockLimit final : public RunObserver<2> {
 public:
  explicit EventsPastAWallClockLimit(double limit) : limit_(limit) {}
  void on_start(const State<2>&) override { started_ = std::chrono::steady_clock::now(); }
  void after_event(const State<2>&, const EventRecord&, const EngineCounters&) override {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count() > limit_) ++late;
  }
  std::int64_t late = 0;

 private:
  double limit_;
  std::chrono::steady_clock::time_point started_;
};

TEST_P(EventDriven, StopsAtTheWallClockLimit) {
  // Elastic bounces: without the limit the run would never end. It stops at the first
  // reading of the clock past the limit, however fast the machine (or slow the build).
  Config c = testing::small_config(2, 150, 0.05, Boundary::periodic, 3);
  c.collision.outcome = CollisionOutcome::bounce;
  State<2> s = make_initial_state<2>(c);
  StopCriteria stop;
  stop.wall_seconds = 0.05;
  EventsPastAWallClockLimit late(stop.wall_seconds);
  const RunResult r = run_engine(s, engine(), {CollisionOutcome::bounce, 1.0, 0.0}, stop, &late);
  EXPECT_EQ(r.reason, StopReason::wall_seconds);
  EXPECT_GE(r.wall_seconds, stop.wall_seconds);
  EXPECT_EQ(r.counters.events % kEventsPerClockCheck, 0);
  EXPECT_LE(late.late, kEventsPerClockCheck);
}

// Asks the run to stop, as SIGTERM does, once it has handled `after` events.
class SignalAfterEvents final : public RunObserver<2> {
 public:
  explicit SignalAfterEvents(std::int64_t after) : after_(after) {}
  void after_event(const State<2>&, const EventRecord&, const EngineCounters&) override {
    if (++events == after_) request_stop_by_signal(SIGTERM);
  }
  std::int64_t events = 0;

 private:
  std::int64_t after_;
};

// ed-naive searches N^2 / 2 pairs for every event: were the clock and the signal flag read
// only every kEventsPerClockCheck events, a run of 10^5 spheres would leave SIGTERM and
// stop.wall_seconds unanswered for hours. From kGuardedSearchSpheres on the search asks the
// guard itself, so such a run stops within the event under way. 600 discs: 1.8e5 pairs.
TEST(EventDrivenNaive, ALargeRunAnswersASignalWithinTheEventUnderWay) {
  Config c = testing::small_config(2, 600, 0.05, Boundary::periodic, 3);
  State<2> s = make_initial_state<2>(c);
  SignalAfterEvents signal(3);
  const RunResult r = run_engine(s, "ed-naive", {CollisionOutcome::bounce, 1.0, 0.0}, {}, &signal);
  clear_stop_signal();
  EXPECT_EQ(r.reason, StopReason::interrupted);
  EXPECT_EQ(signal.events, 3);
  EXPECT_EQ(r.counters.events, 3);
}

TEST(EventDrivenNaive, ALargeRunStopsAtTheWallClockLimitWithinTheEventUnderWay) {
  Config c = testing::small_config(2, 600, 0.05, Boundary::periodic, 3);
  State<2> s = make_initial_state<2>(c);
  StopCriteria stop;
  stop.wall_seconds = 0.05;
  EventsPastAWallClockLimit late(stop.wall_seconds);
  const RunResult r = run_engine(s, "ed-naive", {CollisionOutcome::bounce, 1.0, 0.0}, stop, &late);
  EXPECT_EQ(r.reason, StopReason::wall_seconds);
  EXPECT_GE(r.wall_seconds, stop.wall_seconds);
  EXPECT_LE(late.late, 1);
}

TEST_P(EventDriven, DetectsThatNoCollisionIsPossible) {
  State<2> s = make_state<2>(10, Boundary::periodic, {{vec<2>(2, 2), vec<2>(1, 1)}, {vec<2>(6, 3), vec<2>(1, 1)}});
  EXPECT_EQ(run_engine(s, engine()).reason, StopReason::no_collision_possible);
  State<2> rest = make_state<2>(10, Boundary::walls, {{vec<2>(2, 2), vec<2>(0, 0)}, {vec<2>(6, 3), vec<2>(0, 0)}});
  EXPECT_EQ(run_engine(rest, engine()).reason, StopReason::no_collision_possible);
}

// ---- invariants over random runs -------------------------------------------------------

struct Scenario {
  int dimension;
  Boundary boundary;
  CollisionOutcome outcome;
  double restitution;
  double volume_fraction = 0.15;
};

template <int D>
void check_invariants(const std::string& engine, const Scenario& sc, int n, std::uint64_t seed) {
  Config c = testing::small_config(D, n, sc.volume_fraction, sc.boundary, seed);
  c.initial.velocities = InitialVelocities::gaussian;
  State<D> s = make_initial_state<D>(c);
  const double mass = s.total_mass();
  const Vec<D> p0 = s.momentum();
  const double scale = s.momentum_scale();
  double energy = s.kinetic_energy();
  double worst = -1.0;
  Recorder<D> rec;
  // A missed collision can leave a run without an end. These runs take at most ~40 events
  // per sphere: a bound on the events, not the wall clock, stops one that goes on however
  // fast the machine or slow the build.
  const std::size_t max_events = 1000 * static_cast<std::size_t>(n);
  rec.check = [&](const State<D>& st, const EventRecord&) {
    worst = std::max(worst, worst_overlap(st));
    const double e = st.kinetic_energy();
    EXPECT_LE(e, energy * (1 + 1e-12)) << "kinetic energy increased at t = " << st.time;
    energy = e;
    if (rec.events.size() > max_events) throw std::runtime_error("over 1000 events per sphere: a run without an end");
  };
  StopCriteria stop;
  if (sc.outcome == CollisionOutcome::bounce) stop.time = 20.0;
  run_engine(s, engine, {sc.outcome, sc.restitution, 0.0}, stop, &rec);
  ASSERT_GT(rec.of_kind(EventKind::collision).size(), 10u);
  EXPECT_LE(worst, 1e-9) << "overlap beyond 1e-9 of a diameter";
  EXPECT_DOUBLE_EQ(s.total_mass(), mass);
  int members = 0;
  for (const auto& k : s.clusters) members += k.size();
  EXPECT_EQ(members, n);
  if (sc.boundary == Boundary::periodic) {
    EXPECT_LT((s.momentum() - p0).norm() / scale, 1e-12) << "momentum not conserved";
  }
}

TEST_P(EventDriven, RandomRunsKeepMassMomentumAndNoOverlap2D) {
  const int n = engine() == "ed" ? 200 : 120;
  for (Boundary b : {Boundary::walls, Boundary::periodic}) {
    check_invariants<2>(engine(), {2, b, CollisionOutcome::stick, 0.0}, n, 11);
    check_invariants<2>(engine(), {2, b, CollisionOutcome::bounce, 0.7}, n, 12);
  }
}

TEST_P(EventDriven, RandomRunsKeepMassMomentumAndNoOverlap3D) {
  const int n = engine() == "ed" ? 200 : 120;
  for (Boundary b : {Boundary::walls, Boundary::periodic}) {
    check_invariants<3>(engine(), {3, b, CollisionOutcome::stick, 0.0}, n, 21);
    check_invariants<3>(engine(), {3, b, CollisionOutcome::bounce, 0.7}, n, 22);
  }
}

TEST_P(EventDriven, DilutePeriodicRunsKeepMomentumAndNoOverlap) {
  // Few, long flights: pairs often meet through an image that was not the nearest one
  // when their motion was last predicted.
  const int n = engine() == "ed" ? 200 : 100;
  check_invariants<2>(engine(), {2, Boundary::periodic, CollisionOutcome::stick, 0.0, 0.01}, n, 31);
  check_invariants<3>(engine(), {3, Boundary::periodic, CollisionOutcome::stick, 0.0, 0.01}, n, 32);
}

TEST_P(EventDriven, ElasticBouncesConserveKineticEnergy) {
  Config c = testing::small_config(2, 100, 0.2, Boundary::periodic, 5);
  State<2> s = make_initial_state<2>(c);
  const double e0 = s.kinetic_energy();
  const RunResult r = run_engine(s, engine(), {CollisionOutcome::bounce, 1.0, 0.0}, until(30), nullptr);
  EXPECT_GT(r.counters.collisions, 100);
  EXPECT_NEAR(s.kinetic_energy(), e0, 1e-12 * e0);
}

TEST_P(EventDriven, SameSeedGivesByteIdenticalFinalState) {
  auto final_text = [&](std::uint64_t seed) {
    Config c = testing::small_config(2, 150, 0.2, Boundary::walls, seed);
    State<2> s = make_initial_state<2>(c);
    run_engine(s, engine());
    return state_csv_text(s);
  };
  const std::string a = final_text(7), b = final_text(7), other = final_text(8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, other);
}

// `ed` keeps only the earliest event of each cluster (EventDrivenSettings::calendar) and
// predicts a cluster afresh after each of its events, stale ones included: the run is the
// same event for event as with every prediction kept, for sticking and bouncing, walls and
// periodic faces.
template <int D>
void same_run_whatever_is_kept(Config c, const CollisionSettings& law, const StopCriteria& stop) {
  auto run = [&](CalendarKeeps keeps, RunResult& r) {
    State<D> s = make_initial_state<D>(c);
    RunObserver<D> none;
    EventDrivenSettings settings{law, std::nullopt};
    settings.calendar = keeps;
    r = make_event_driven_engine<D>(settings)->run(s, stop, none);
    return state_csv_text(s);
  };
  RunResult all, earliest;
  const std::string text_all = run(CalendarKeeps::every_event, all);
  EXPECT_GT(all.counters.collisions, 50);
  EXPECT_EQ(run(CalendarKeeps::earliest_only, earliest), text_all);
  EXPECT_EQ(earliest.counters.events, all.counters.events);
  EXPECT_EQ(earliest.counters.collisions, all.counters.collisions);
  EXPECT_EQ(earliest.counters.wall_bounces, all.counters.wall_bounces);
  EXPECT_EQ(earliest.count("list_rebuilds"), all.count("list_rebuilds"));
  EXPECT_LT(earliest.count("event_queue_peak"), all.count("event_queue_peak"));
  EXPECT_GT(earliest.count("pair_predictions"), all.count("pair_predictions"));  // predicted afresh
}

template <int D>
void meets_after_turning_back(CollisionOutcome outcome) {
  State<D> s = testing::turning_sphere_and_rebuilt_partner<D>();
  Recorder<D> rec;
  rec.check = [](const State<D>& st, const EventRecord&) { EXPECT_LE(worst_overlap(st), 1e-9) << "t = " << st.time; };
  const CollisionSettings law{outcome, 1.0, 0.0};
  const RunResult r = make_event_driven_engine<D>({law, testing::kTurningSkin})->run(s, until(1.3), rec);
  EXPECT_EQ(r.counters.wall_bounces, 1);
  const auto rebuilds = rec.of_kind(EventKind::list_rebuild);
  ASSERT_FALSE(rebuilds.empty());
  EXPECT_DOUBLE_EQ(rebuilds[0].time, 0.625);  // sphere 1's, as the scenario needs
  const auto hits = rec.of_kind(EventKind::collision);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_NEAR(hits[0].time, testing::kTurningContact, 1e-12);
}

TEST(EventDrivenLists, ASphereTurningBackMeetsAPartnerThatRebuiltWhileItWasAway) {
  for (CollisionOutcome outcome : {CollisionOutcome::stick, CollisionOutcome::bounce}) {
    meets_after_turning_back<2>(outcome);
    meets_after_turning_back<3>(outcome);
  }
}

TEST(EventDrivenSkin, ADenseBouncingGasListsBeyondItsContactShell) {
  // 3D at volume fraction 0.45: the neighbours' rule would give a skin shorter than a free
  // path. A gas that bounces gets kMinBouncingSkin; one that aggregates keeps the rule,
  // floored at kMinSkin.
  Config c = testing::small_config(3, 512, 0.45, Boundary::periodic, 1);
  c.initial.positions = InitialPositions::lattice;
  const State<3> dense = make_initial_state<3>(c);
  const double r = dense.mean_radius();
  EXPECT_DOUBLE_EQ(default_skin(dense, CollisionOutcome::bounce), kMinBouncingSkin * r);
  EXPECT_DOUBLE_EQ(default_skin(dense, CollisionOutcome::stick), kMinSkin * r);
  EXPECT_DOUBLE_EQ(default_skin(dense, CollisionOutcome::energy_threshold), kMinSkin * r);
  // Dilute, the rule's skin is longer than either floor, whatever the outcome.
  c.system.volume_fraction = 0.05;
  const State<3> dilute = make_initial_state<3>(c);
  EXPECT_GT(default_skin(dilute, CollisionOutcome::stick), kMinBouncingSkin * r);
  EXPECT_EQ(default_skin(dilute, CollisionOutcome::bounce), default_skin(dilute, CollisionOutcome::stick));
}

// Keeping the earliest event only also prunes each prediction against the earliest event
// found so far (collision/contact_time.hpp, contact_time_within); keeping every event
// does not: the two runs agreeing checks the pruning as well.
TEST(EventDrivenKeptEvents, KeepingOnlyTheEarliestEventsChangesNoResult) {
  StopCriteria to_one;
  StopCriteria until_20 = until(20.0);
  {
    SCOPED_TRACE("2D walls, lattice, stick");
    Config c = testing::small_config(2, 900, 0.2, Boundary::walls, 3);
    c.initial.positions = InitialPositions::lattice;
    same_run_whatever_is_kept<2>(c, {}, to_one);
  }
  {
    SCOPED_TRACE("3D periodic, random, stick");
    Config c = testing::small_config(3, 600, 0.2, Boundary::periodic, 4);
    c.initial.zero_momentum = true;
    same_run_whatever_is_kept<3>(c, {}, to_one);
  }
  {
    SCOPED_TRACE("2D periodic, bounce 0.9");
    same_run_whatever_is_kept<2>(testing::small_config(2, 400, 0.3, Boundary::periodic, 5),
                                 {CollisionOutcome::bounce, 0.9, 0.0}, until_20);
  }
  {
    SCOPED_TRACE("3D walls, elastic");
    same_run_whatever_is_kept<3>(testing::small_config(3, 400, 0.3, Boundary::walls, 6),
                                 {CollisionOutcome::bounce, 1.0, 0.0}, until_20);
  }
}

}  // namespace
}  // namespace ballagg
