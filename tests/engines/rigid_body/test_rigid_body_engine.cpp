// The rigid-body engine (Richardson 1995): conservation laws through coagulation and
// restitution of off-centre collisions of spinning aggregates, contact times on rotating
// trajectories against a brute-force reference, exact states for observers, and 2D.
#include <cmath>
#include <functional>
#include <numbers>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "ballagg/analysis/overlap.hpp"
#include "ballagg/collision/contact_time.hpp"
#include "ballagg/core/inertia.hpp"
#include "ballagg/engines/rigid_body/rigid_body_engine.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::Ball;
using testing::vec;

// Totals of a state of rigid bodies, from its clusters and their spins.
template <int D>
struct Totals {
  Vec<D> momentum = Vec<D>::Zero();
  Spin<D> angular_momentum = Spin<D>::Zero();  // about the origin
  double energy = 0.0;                          // translation + rotation
  double momentum_scale = 0.0, angular_scale = 0.0;
  explicit Totals(const State<D>& s) {
    for (int c : s.alive_clusters()) {
      const Cluster<D>& k = s.clusters[c];
      const Spin<D> orbital = k.mass * cross(s.origin(c, s.time), k.velocity);
      momentum += k.mass * k.velocity;
      angular_momentum += orbital + s.spin[c].angular_momentum;
      energy += 0.5 * k.mass * k.velocity.squaredNorm() + s.spin[c].energy();
      momentum_scale += k.mass * k.velocity.norm();
      angular_scale += orbital.norm() + s.spin[c].angular_momentum.norm();
    }
  }
};

// An observer that reads the state exactly after every event.
template <int D>
class Watcher final : public RunObserver<D> {
 public:
  std::function<void(const State<D>&, const EventRecord&)> check;
  std::vector<EventRecord> collisions;
  double next_position_read() const override { return -std::numeric_limits<double>::infinity(); }
  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters&) override {
    if (e.kind == EventKind::collision) collisions.push_back(e);
    if (check) check(s, e);
  }
};

template <int D>
RunResult run_rigid(State<D>& s, RigidBodySettings settings, StopCriteria stop, RunObserver<D>& observer) {
  return make_rigid_body_engine<D>(settings)->run(s, stop, observer);
}

template <int D>
void set_spin(State<D>& s, int cluster, const Spin<D>& w) {
  if (s.spin.empty()) s.spin.resize(s.clusters.size());
  s.spin[cluster].angular_velocity = w;
}

// Two aggregates (an L-shaped tetramer and a bent trimer) flying at each other off-centre,
// both spinning, in a box large enough that no wall is reached.
template <int D>
State<D> spinning_pair(double gap) {
  std::vector<Ball<D>> balls;
  const double r = 0.5;
  for (const Vec<D>& x : {vec<D>(10, 10, 10), vec<D>(11, 10, 10), vec<D>(12, 10, 10), vec<D>(12, 11, 10)})
    balls.push_back({x, vec<D>(0.6, 0.1, -0.05), r, 1.0, 0});
  for (const Vec<D>& x : {vec<D>(15 + gap, 10.7, 10.3), vec<D>(16 + gap, 10.7, 10.3), vec<D>(16.5 + gap, 10.7 + 0.5 * std::sqrt(3.0), 10.3)})
    balls.push_back({x, vec<D>(-0.7, 0.0, 0.1), r, 1.5, 1});
  State<D> s = testing::make_state<D>(30.0, Boundary::walls, balls);
  if constexpr (D == 3) {
    set_spin<D>(s, 0, Spin<D>(0.3, -0.8, 1.1));
    set_spin<D>(s, 1, Spin<D>(-0.9, 0.4, 0.7));
  } else {
    set_spin<D>(s, 0, Spin<D>(0.9));
    set_spin<D>(s, 1, Spin<D>(-1.3));
  }
  return s;
}

template <int D>
void expect_conserved(const Totals<D>& before, const Totals<D>& after, bool energy) {
  EXPECT_LT((after.momentum - before.momentum).norm(), 1e-12 * before.momentum_scale);
  EXPECT_LT((after.angular_momentum - before.angular_momentum).norm(), 1e-12 * before.angular_scale);
  if (energy) {
    EXPECT_NEAR(after.energy, before.energy, 1e-12 * before.energy);
  }
}

// The spinning pair with its bodies built (spins turned into angular momenta) by a run
// that stops at once.
template <int D>
State<D> prepared_pair() {
  State<D> s = spinning_pair<D>(0.5);
  RunObserver<D> none;
  StopCriteria now;
  now.time = 1e-12;
  run_rigid(s, {}, now, none);
  return s;
}

template <int D>
void stick_conserves_momenta() {
  State<D> s = prepared_pair<D>();
  Watcher<D> w;
  const Totals<D> before(s);
  StopCriteria merged;
  merged.clusters = 1;
  const RunResult r = run_rigid(s, {}, merged, w);
  ASSERT_EQ(r.reason, StopReason::clusters);
  ASSERT_EQ(s.n_clusters(), 1);
  expect_conserved(before, Totals<D>(s), false);
  EXPECT_LT(Totals<D>(s).energy, before.energy);
  EXPECT_LT(testing::worst_overlap(s), 1e-9);
}
TEST(RigidBodyEngine, OffCentreCoagulationOfSpinningAggregatesConservesMomenta3D) { stick_conserves_momenta<3>(); }
TEST(RigidBodyEngine, OffCentreCoagulationOfSpinningAggregatesConservesMomenta2D) { stick_conserves_momenta<2>(); }

template <int D>
void bounce_conserves(double eps) {
  State<D> s = prepared_pair<D>();
  Watcher<D> w;
  const Totals<D> before(s);
  RigidBodySettings settings;
  settings.collision.outcome = CollisionOutcome::bounce;
  settings.collision.restitution = eps;
  StopCriteria later;
  later.time = 8.0;  // after the first contacts, before any wall
  run_rigid(s, settings, later, w);
  ASSERT_FALSE(w.collisions.empty());
  const Totals<D> after(s);
  expect_conserved(before, after, eps == 1.0);
  if (eps < 1.0) {
    EXPECT_LT(after.energy, before.energy * (1 - 1e-6));
  }
  EXPECT_LT(testing::worst_overlap(s), 1e-9);
}
TEST(RigidBodyEngine, ElasticBounceOfSpinningAggregatesConservesMomentaAndEnergy3D) { bounce_conserves<3>(1.0); }
TEST(RigidBodyEngine, ElasticBounceOfSpinningAggregatesConservesMomentaAndEnergy2D) { bounce_conserves<2>(1.0); }
TEST(RigidBodyEngine, InelasticBounceDissipatesAndConservesMomenta3D) { bounce_conserves<3>(0.4); }
TEST(RigidBodyEngine, InelasticBounceDissipatesAndConservesMomenta2D) { bounce_conserves<2>(0.4); }

TEST(RigidBodyEngine, CatastrophicFragmentationConservesMomentaAndEnergy) {
  // Section 2.6: the impacting aggregates join, then every sphere flies off with its rigid
  // velocity plus a radial velocity that gives back the energy the joining lost.
  State<3> s = prepared_pair<3>();
  Watcher<3> w;
  const Totals<3> before(s);
  RigidBodySettings settings;
  settings.law.fragmentation_energy = 1e-6;  // every impact breaks
  StopCriteria first;
  first.time = 8.0;
  w.check = [&](const State<3>& st, const EventRecord& e) {
    if (e.kind != EventKind::collision || w.collisions.size() != 1) return;
    EXPECT_EQ(st.n_clusters(), 7);  // every sphere on its own
    const Totals<3> after(st);
    expect_conserved(before, after, true);
  };
  const RunResult r = run_rigid(s, settings, first, w);
  EXPECT_EQ(r.count("fragmentations"), 1);
  EXPECT_LT(testing::worst_overlap(s), 1e-9);
}

// Round-off allowed in the breakup's budgets, relative to the pre-impact energy and momentum
// scales: the breakup is exact in exact arithmetic (sum m r = 0, r x H r = 0).
constexpr double kBreakupRoundOff = 1e-12;

// Section 2.6 as the engine does it, piece by piece: the two bodies (spinning, off-centre)
// join, then each sphere leaves with V + omega x r + H r, r from the joined centre of mass,
// one H > 0 for all, which gives back the energy the joining lost; each keeps the spin.
template <int D>
void breakup_gives_back_the_pre_impact_energy() {
  State<D> s = prepared_pair<D>();
  const Totals<D> before(s);
  double mass = 0.0;
  Vec<D> centre_of_mass_velocity = Vec<D>::Zero();
  for (int c : s.alive_clusters()) {
    mass += s.clusters[c].mass;
    centre_of_mass_velocity += s.clusters[c].mass * s.clusters[c].velocity;
  }
  centre_of_mass_velocity /= mass;
  RigidBodySettings settings;
  settings.law.fragmentation = Fragmentation::energy;
  settings.law.fragmentation_energy = 1e-6;  // every impact breaks
  Watcher<D> w;
  int checked = 0;
  w.check = [&](const State<D>& st, const EventRecord& e) {
    if (e.kind != EventKind::collision || w.collisions.size() != 1) return;
    ASSERT_EQ(st.n_clusters(), 7);  // every sphere on its own
    const Totals<D> after(st);
    EXPECT_LT((after.momentum - before.momentum).norm(), kBreakupRoundOff * before.momentum_scale);
    EXPECT_LT((after.angular_momentum - before.angular_momentum).norm(), kBreakupRoundOff * before.angular_scale);
    EXPECT_NEAR(after.energy, before.energy, kBreakupRoundOff * before.energy);  // translation + rotation
    Vec<D> centre = Vec<D>::Zero();
    for (int c : st.alive_clusters()) centre += st.clusters[c].mass * st.origin(c, st.time);
    centre /= mass;
    double expansion = 0.0;
    for (int c : st.alive_clusters()) {
      const Vec<D> r = st.origin(c, st.time) - centre;
      const Vec<D> radial = st.clusters[c].velocity - centre_of_mass_velocity - cross(st.spin[c].angular_velocity, r);
      const double h = radial.dot(r) / r.squaredNorm();
      EXPECT_GT(h, 0.0);                                                 // outward
      EXPECT_LT((radial - h * r).norm(), 1e-9 * radial.norm());          // radial
      if (expansion == 0.0) expansion = h;
      EXPECT_NEAR(h, expansion, 1e-9 * expansion);                       // one H for all: homologous
    }
    ++checked;
  };
  StopCriteria first;
  first.time = 8.0;
  const RunResult r = run_rigid(s, settings, first, w);
  EXPECT_EQ(r.count("fragmentations"), 1);
  EXPECT_EQ(checked, 1);
}
TEST(RigidBodyEngine, BreakupGivesBackThePreImpactEnergyByAnOutwardRadialVelocity3D) {
  breakup_gives_back_the_pre_impact_energy<3>();
}
TEST(RigidBodyEngine, BreakupGivesBackThePreImpactEnergyByAnOutwardRadialVelocity2D) {
  breakup_gives_back_the_pre_impact_energy<2>();
}

// ---- contact times against a brute-force reference -----------------------------------------

// A body integrated independently of the engine: centre in a straight line, orientation by
// RK4 of dR/dt = [omega]x R with omega = R I0^-1 R^T h (I0: the inertia tensor at t = 0).
struct ReferenceBody {
  Vec<3> centre, velocity, h;
  InertiaTensor<3> inertia_inverse;
  std::vector<Vec<3>> arms;  // sphere centres - centre of mass, at t = 0
  Rotation<3> rotation = Rotation<3>::Identity();
  double time = 0.0;

  // Advances the orientation to time t in RK4 steps of at most 1e-4.
  void advance_to(double t) {
    auto rate = [&](const Rotation<3>& r) {
      const Vec<3> w = r * inertia_inverse * r.transpose() * h;
      Rotation<3> s;
      s << 0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0;
      return Rotation<3>(s * r);
    };
    const int steps = std::max(1, static_cast<int>(std::ceil((t - time) / 1e-4)));
    const double dt = (t - time) / steps;
    for (int k = 0; k < steps; ++k) {
      const Rotation<3> k1 = rate(rotation), k2 = rate(rotation + 0.5 * dt * k1), k3 = rate(rotation + 0.5 * dt * k2),
                        k4 = rate(rotation + dt * k3);
      rotation += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    time = t;
  }
  Vec<3> sphere(std::size_t k) const { return centre + time * velocity + rotation * arms[k]; }
};

ReferenceBody reference_body(const State<3>& s, int c) {
  ReferenceBody b;
  std::vector<Vec<3>> x;
  std::vector<double> r, m;
  for (int i : s.clusters[c].members) {
    x.push_back(s.unwrapped_position(i, 0.0));
    r.push_back(s.spheres.radius[i]);
    m.push_back(s.spheres.mass[i]);
  }
  const MassProperties<3> p = sphere_mass_properties<3>(x, r, m);
  b.centre = p.centre;
  b.velocity = s.clusters[c].velocity;
  b.h = p.inertia * s.spin[c].angular_velocity;
  b.inertia_inverse = p.inertia.inverse();
  for (const Vec<3>& xi : x) b.arms.push_back(xi - p.centre);
  return b;
}

// Smallest gap between the spheres (radius r) of the two bodies at their common time.
double reference_gap(const ReferenceBody& a, const ReferenceBody& b, double r) {
  double gap = 1e300;
  for (std::size_t p = 0; p < a.arms.size(); ++p)
    for (std::size_t q = 0; q < b.arms.size(); ++q) gap = std::min(gap, (a.sphere(p) - b.sphere(q)).norm() - 2 * r);
  return gap;
}

void expect_contact_time_matches_reference(State<3> s) {
  ReferenceBody a = reference_body(s, 0), b = reference_body(s, 1);
  Watcher<3> w;
  StopCriteria merged;
  merged.clusters = 1;
  run_rigid(s, {}, merged, w);
  ASSERT_EQ(w.collisions.size(), 1u);
  const double engine = w.collisions.front().time;
  // Brute force: fine steps to the first sign change of the gap, then bisection.
  const double r = 0.5, step = 1e-3;
  double lo = 0.0, hi = -1.0;
  for (double t = step; t < 30.0; t += step) {
    a.advance_to(t);
    b.advance_to(t);
    if (reference_gap(a, b, r) <= 0.0) {
      hi = t;
      break;
    }
    lo = t;
  }
  ASSERT_GT(hi, 0.0) << "the reference bodies never touch";
  ReferenceBody a_lo = a, b_lo = b;
  a_lo.rotation = b_lo.rotation = Rotation<3>::Identity();
  a_lo.time = b_lo.time = 0.0;
  a_lo.advance_to(lo);
  b_lo.advance_to(lo);
  for (int k = 0; k < 45; ++k) {
    const double mid = 0.5 * (lo + hi);
    ReferenceBody am = a_lo, bm = b_lo;
    am.advance_to(mid);
    bm.advance_to(mid);
    if (reference_gap(am, bm, r) > 0.0) {
      lo = mid;
      a_lo = am;
      b_lo = bm;
    } else {
      hi = mid;
    }
  }
  ReferenceBody a1 = a_lo, b1 = b_lo;
  a1.advance_to(lo + 1e-6);
  b1.advance_to(lo + 1e-6);
  const double rate = (reference_gap(a1, b1, r) - reference_gap(a_lo, b_lo, r)) / 1e-6;
  // The engine's contact lies within 1e-9 of a diameter of the reference's.
  EXPECT_LT(std::abs(engine - hi) * std::abs(rate), 1e-9 * 2 * r) << "engine " << engine << " reference " << hi;
}

TEST(RigidBodyEngine, ContactTimeOfSpinningAggregatesMatchesBruteForce) {
  expect_contact_time_matches_reference(spinning_pair<3>(0.5));
}

TEST(RigidBodyEngine, SpinningAggregateHitsANeighbourWhoseCentreRecedes) {
  // The centres drift apart; the arm of the fast-spinning trimer sweeps into the monomer.
  std::vector<Ball<3>> balls;
  for (const Vec<3>& x : {vec<3>(10, 10, 10), vec<3>(11, 10, 10), vec<3>(12, 10, 10)})
    balls.push_back({x, vec<3>(-0.05, 0, 0), 0.5, 1.0, 0});
  balls.push_back({vec<3>(11, 11.9, 10), vec<3>(0, 0.05, 0), 0.5, 1.0, 1});
  State<3> s = testing::make_state<3>(30.0, Boundary::walls, balls);
  set_spin<3>(s, 0, Spin<3>(0.0, 0.2, 3.0));
  const Vec<3> dx = s.unwrapped_position(3, 0.0) - Vec<3>(11, 10, 10);
  ASSERT_GT(dx.dot(s.clusters[1].velocity - s.clusters[0].velocity), 0.0);  // receding
  expect_contact_time_matches_reference(s);
}

// ---- many bodies ---------------------------------------------------------------------------

template <int D>
State<D> random_gas(int n, double volume_fraction, Boundary boundary, std::uint64_t seed) {
  Config c = testing::small_config(D, n, volume_fraction, boundary, seed);
  c.engine.kind = EngineKind::rigid_body;
  c.initial.velocities = InitialVelocities::gaussian;
  return make_initial_state<D>(c);
}

template <int D>
void no_overlap_in_a_random_run(Boundary boundary, CollisionOutcome outcome) {
  State<D> s = random_gas<D>(150, 0.08, boundary, 5);
  RigidBodySettings settings;
  settings.collision.outcome = outcome;
  settings.collision.restitution = 0.5;
  settings.law.energy_threshold = 0.4;
  settings.collision.tc_time = 1e-9;
  Watcher<D> w;
  double worst = -1.0;
  w.check = [&](const State<D>& st, const EventRecord& e) {
    if (e.kind == EventKind::collision) worst = std::max(worst, testing::worst_overlap(st));
  };
  StopCriteria stop;
  stop.clusters = 10;
  stop.time = 60.0;
  run_rigid(s, settings, stop, w);
  EXPECT_GT(w.collisions.size(), 100u);
  EXPECT_LT(worst, 1e-9);
}
TEST(RigidBodyEngine, NoOverlapInARandomPeriodicRun3D) { no_overlap_in_a_random_run<3>(Boundary::periodic, CollisionOutcome::stick); }
TEST(RigidBodyEngine, NoOverlapInARandomRunWithWallsAndBounces3D) {
  no_overlap_in_a_random_run<3>(Boundary::walls, CollisionOutcome::energy_threshold);
}
TEST(RigidBodyEngine, NoOverlapInARandomRunWithWallsAndBounces2D) {
  no_overlap_in_a_random_run<2>(Boundary::walls, CollisionOutcome::energy_threshold);
}
TEST(RigidBodyEngine, NoOverlapInARandomPeriodicRun2D) { no_overlap_in_a_random_run<2>(Boundary::periodic, CollisionOutcome::stick); }

TEST(RigidBodyEngine, NoOverlapThroughThousandsOfBouncesAndMergesOfSpinningBodies) {
  // Richardson's model (iv) rules on 400 spheres: every collision, the largest overlap in
  // the whole state (grid search) stays below 1e-9 of a contact distance.
  State<3> s = random_gas<3>(400, 0.03, Boundary::periodic, 21);
  RigidBodySettings settings;
  settings.collision.outcome = CollisionOutcome::energy_threshold;
  settings.law.energy_threshold = 0.5 * s.kinetic_energy() / s.n_clusters();
  settings.law.restitution_law = RestitutionLaw::bridges;
  settings.law.velocity_unit = 0.01;
  settings.collision.tc_time = 1e-9;
  Watcher<3> w;
  double worst = -1.0;
  w.check = [&](const State<3>& st, const EventRecord& e) {
    if (e.kind == EventKind::collision) worst = std::max(worst, max_relative_overlap(st).value_or(-1.0));
  };
  StopCriteria stop;
  stop.time = 60.0;
  run_rigid(s, settings, stop, w);
  EXPECT_GT(w.collisions.size(), 1000u);
  EXPECT_LT(worst, 1e-9);
}

template <int D>
void rigid_meets_after_turning_back() {
  State<D> s = testing::turning_sphere_and_rebuilt_partner<D>();
  Watcher<D> watch;
  watch.check = [](const State<D>& st, const EventRecord&) {
    EXPECT_LE(testing::worst_overlap(st), 1e-9) << "t = " << st.time;
  };
  RigidBodySettings settings;
  settings.skin = testing::kTurningSkin;
  StopCriteria stop;
  stop.clusters = 0;
  stop.time = 1.3;
  run_rigid(s, settings, stop, watch);
  ASSERT_EQ(watch.collisions.size(), 1u);
  EXPECT_NEAR(watch.collisions[0].time, testing::kTurningContact, 1e-9);
}

TEST(RigidBodyEngine, ASphereTurningBackMeetsAPartnerThatRebuiltWhileItWasAway) {
  rigid_meets_after_turning_back<2>();
  rigid_meets_after_turning_back<3>();
}

TEST(RigidBodyEngine, PeriodicRunConservesMomentum) {
  State<3> s = random_gas<3>(300, 0.05, Boundary::periodic, 9);
  const Vec<3> p0 = s.momentum();
  const double scale = s.momentum_scale();
  RigidBodySettings settings;
  settings.collision.outcome = CollisionOutcome::energy_threshold;
  settings.law.energy_threshold = 0.5;
  settings.collision.restitution = 0.8;
  Watcher<3> w;
  StopCriteria stop;
  stop.time = 30.0;
  run_rigid(s, settings, stop, w);
  EXPECT_GT(w.collisions.size(), 200u);
  EXPECT_LT((s.momentum() - p0).norm(), 1e-12 * scale);
}

TEST(RigidBodyEngine, WallsAreElasticAndKeepEveryBodyInside) {
  State<3> s = random_gas<3>(60, 0.1, Boundary::walls, 4);
  RigidBodySettings settings;
  settings.collision.outcome = CollisionOutcome::stick;
  Watcher<3> w;
  StopCriteria grow;
  grow.clusters = 6;
  run_rigid(s, settings, grow, w);  // spinning aggregates
  double e0 = Totals<3>(s).energy;
  int wall_hits = 0;
  double outside = 0.0;
  w.check = [&](const State<3>& st, const EventRecord& e) {
    if (e.kind == EventKind::wall) ++wall_hits;
    for (int i = 0; i < st.n_spheres(); ++i)
      for (int a = 0; a < 3; ++a) {
        const double x = st.unwrapped_position(i, st.time)[a], r = st.spheres.radius[i];
        outside = std::max({outside, (r - x) / r, (x + r - st.box.length) / r});
      }
  };
  settings.collision.outcome = CollisionOutcome::bounce;  // elastic between bodies too: energy is conserved
  StopCriteria stop;
  stop.time = s.time + 40.0;
  run_rigid(s, settings, stop, w);
  EXPECT_GT(wall_hits, 20);
  EXPECT_LT(outside, 1e-9);
  EXPECT_NEAR(Totals<3>(s).energy, e0, 1e-10 * e0);
}

// ---- observers see exact states -------------------------------------------------------------

// Reads positions at fixed times between events.
class Sampler final : public RunObserver<3> {
 public:
  std::vector<double> times;
  std::vector<std::vector<Vec<3>>> frames;
  double next_position_read() const override { return next_ < times.size() ? times[next_] : kNever; }
  void before_event(const State<3>& s, double t) override {
    while (next_ < times.size() && times[next_] < t) {
      std::vector<Vec<3>> x;
      for (int i = 0; i < s.n_spheres(); ++i) x.push_back(s.position(i, times[next_]));
      frames.push_back(x);
      ++next_;
    }
  }

 private:
  std::size_t next_ = 0;
};

TEST(RigidBodyEngine, ObserversReadingPositionsBetweenEventsSeeTheExactState) {
  const State<3> start = random_gas<3>(200, 0.03, Boundary::periodic, 8);
  RigidBodySettings settings;
  Sampler sampler;
  sampler.times = {0.7, 1.9, 3.3};
  {
    State<3> s = start;
    StopCriteria stop;
    stop.time = 4.0;
    const RunResult r = run_rigid(s, settings, stop, sampler);
    EXPECT_EQ(r.reason, StopReason::time) << s.n_clusters() << " " << s.time;
  }
  ASSERT_EQ(sampler.frames.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    State<3> s = start;
    RunObserver<3> none;
    StopCriteria stop;
    stop.time = sampler.times[k];
    run_rigid(s, settings, stop, none);
    double worst = 0.0;
    for (int i = 0; i < s.n_spheres(); ++i)
      worst = std::max(worst, s.box.separation(s.position(i, s.time), sampler.frames[k][i]).norm());
    EXPECT_LT(worst, 1e-12) << "frame at t = " << sampler.times[k];
  }
}

// Sphere coalescence (model ii, constant density) takes out and puts back only the spheres a
// merge changes, so a merge costs a few pair predictions (a rebuild of every list would cost
// hundreds at this N); the run keeps mass and momentum and leaves no overlap after any merge.
// Radii grow past twice their start, so the grid is built again on the way.
constexpr double kPredictionsPerMerge = 40.0;

template <int D>
void expect_cheap_exact_coalescence(Boundary boundary) {
  SCOPED_TRACE(fmt::format("D = {}, {}", D, boundary == Boundary::periodic ? "periodic" : "walls"));
  State<D> s = random_gas<D>(800, 0.02, boundary, 31);
  const double mass = s.total_mass();
  const Vec<D> p0 = s.momentum();
  const double scale = s.momentum_scale();
  RigidBodySettings settings;
  settings.law.coagulation = Coagulation::sphere;
  Watcher<D> w;
  double worst = -1.0;
  w.check = [&](const State<D>& st, const EventRecord& e) {
    if (e.merges > 0) worst = std::max(worst, max_relative_overlap(st).value_or(-1.0));
  };
  StopCriteria stop;
  stop.clusters = 80;
  const RunResult r = run_rigid(s, settings, stop, w);
  EXPECT_EQ(s.n_clusters(), 80);
  EXPECT_GT(s.max_radius(), 2.0 * 0.5);
  EXPECT_NEAR(s.total_mass(), mass, 1e-12 * mass);
  if (boundary == Boundary::periodic) {
    EXPECT_LT((s.momentum() - p0).norm(), 1e-12 * scale);
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(static_cast<double>(r.count("pair_predictions")), kPredictionsPerMerge * r.counters.merges);
}

TEST(RigidBodyEngine, SphereCoalescenceIsLocalExactAndConservative) {
  for (Boundary b : {Boundary::periodic, Boundary::walls}) {
    expect_cheap_exact_coalescence<2>(b);
    expect_cheap_exact_coalescence<3>(b);
  }
}

// ---- test models ---------------------------------------------------------------------------

// Model (i): constant kernel A = sigma <v> / V, N(t) = N(0) / (1 + alpha N(0) t / 2) (30).
TEST(RigidBodyEngine, ConstantKernelNumberFollowsTheAnalyticSolution) {
  const int n0 = 400, runs = 8;
  const double radius = 0.1, box = 10.0 * std::cbrt(0.4), speed = 10.0;
  const double alpha = std::numbers::pi * 4 * radius * radius * (4.0 / 3.0 * speed) / (box * box * box);
  const std::vector<double> times{0.2, 0.5, 1.0, 2.0};
  std::vector<std::vector<double>> counts(times.size());
  for (int run = 0; run < runs; ++run) {
    Config c;
    c.system.dimension = 3;
    c.system.n = n0;
    c.system.box_length = box;
    c.system.radius = radius;
    c.system.boundary = Boundary::periodic;
    c.initial.positions = InitialPositions::random;
    c.initial.speed = speed;
    c.initial.seed = 100 + run;
    c.engine.kind = EngineKind::rigid_body;
    State<3> s = make_initial_state<3>(c);
    RigidBodySettings settings;
    settings.law.coagulation = Coagulation::sphere;
    settings.law.merged_radius = MergedRadius::fixed;
    settings.law.constant_speed = true;
    settings.initial_speed = speed;
    class Counter final : public RunObserver<3> {
     public:
      const std::vector<double>* times;
      std::vector<int> at;
      void before_event(const State<3>& st, double t) override {
        while (at.size() < times->size() && (*times)[at.size()] < t) at.push_back(st.n_clusters());
      }
    } counter;
    counter.times = &times;
    StopCriteria stop;
    stop.time = times.back() + 1e-9;
    run_rigid(s, settings, stop, counter);
    ASSERT_EQ(counter.at.size(), times.size());
    for (std::size_t k = 0; k < times.size(); ++k) counts[k].push_back(counter.at[k]);
  }
  for (std::size_t k = 0; k < times.size(); ++k) {
    double mean = 0.0, square = 0.0;
    for (double n : counts[k]) mean += n / runs;
    for (double n : counts[k]) square += (n - mean) * (n - mean) / (runs - 1);
    const double error = std::sqrt(square / runs);  // standard deviation of the mean
    const double theory = n0 / (1.0 + 0.5 * alpha * n0 * times[k]);
    EXPECT_LT(std::abs(mean - theory), 3.0 * std::max(error, 1.0)) << "t = " << times[k] << " mean " << mean;
  }
}

}  // namespace
}  // namespace ballagg
