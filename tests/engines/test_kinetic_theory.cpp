// The event-driven engine against the kinetic theory of hard-sphere gases: collision
// frequencies of elastic gases in equilibrium (Enskog) and the cooling of an inelastic gas
// (Haff's law). These check contact detection statistically, over millions of pairs.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "support.hpp"

namespace ballagg {
namespace {
using testing::run_engine;

// Counts collisions after an equilibration time and records the temperature.
template <int D>
class CollisionCounter final : public RunObserver<D> {
 public:
  explicit CollisionCounter(double from) : from_(from) {}
  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters&) override {
    if (e.kind == EventKind::collision && s.time >= from_) ++collisions;
  }
  std::int64_t collisions = 0;

 private:
  double from_;
};

// Per-particle collision frequency of an elastic gas: 2D  omega = 2 n sigma chi sqrt(pi T / m),
// 3D omega = 4 n sigma^2 chi sqrt(pi T / m); chi is the pair correlation at contact
// (Henderson in 2D, Carnahan-Starling in 3D), T = <v_x^2> with m = 1.
template <int D>
double enskog_frequency(double n_density, double sigma, double phi, double temperature) {
  if constexpr (D == 2) {
    const double chi = (1 - 7 * phi / 16) / ((1 - phi) * (1 - phi));
    return 2 * n_density * sigma * chi * std::sqrt(std::numbers::pi * temperature);
  } else {
    const double chi = (1 - phi / 2) / std::pow(1 - phi, 3);
    return 4 * n_density * sigma * sigma * chi * std::sqrt(std::numbers::pi * temperature);
  }
}

template <int D>
void expect_enskog_rate(double phi, int n, double tolerance) {
  Config c = testing::small_config(D, n, phi, Boundary::periodic, 17);
  c.initial.velocities = InitialVelocities::gaussian;
  c.initial.zero_momentum = true;
  State<D> s = make_initial_state<D>(c);
  const double temperature = 2.0 * s.kinetic_energy() / (D * n);  // conserved: elastic
  const double density = n / s.box.volume();
  const double omega = enskog_frequency<D>(density, 1.0, phi, temperature);
  // Equilibrate for ~10 collisions per sphere (random placement is not an equilibrium
  // structure), then count over ~40 more.
  const double start = 10.0 / omega, span = 40.0 / omega;
  CollisionCounter<D> counter(start);
  StopCriteria stop;
  stop.clusters = 0;
  stop.time = start + span;
  run_engine(s, "ed", {CollisionOutcome::bounce, 1.0, 0.0}, stop, &counter);
  const double measured = 2.0 * counter.collisions / (n * span);
  EXPECT_NEAR(measured / omega, 1.0, tolerance) << "measured " << measured << ", Enskog " << omega;
}

TEST(KineticTheory, ElasticDiscGasCollidesAtTheEnskogRate) {
  expect_enskog_rate<2>(0.05, 2000, 0.02);
  expect_enskog_rate<2>(0.2, 2000, 0.02);
}

TEST(KineticTheory, ElasticSphereGasCollidesAtTheEnskogRate) {
  expect_enskog_rate<3>(0.05, 2000, 0.02);
  expect_enskog_rate<3>(0.2, 2000, 0.02);
}

TEST(KineticTheory, CoolingGranularGasFollowsHaffsLaw) {
  // Homogeneous cooling: dT/dt = -(1 - eps^2) omega T / d with omega proportional to
  // sqrt(T), so sqrt(T0 / T) = 1 + (1 - eps^2) omega0 t / (2 d): a straight line whose
  // slope follows from the collision frequency the run itself measures.
  constexpr int n = 3000;
  constexpr double eps = 0.9;
  Config c = testing::small_config(2, n, 0.1, Boundary::periodic, 8);
  c.initial.velocities = InitialVelocities::gaussian;
  c.initial.zero_momentum = true;
  State<2> s = make_initial_state<2>(c);
  TimeseriesRecorder<2> series(2.0);
  StopCriteria stop;
  stop.clusters = 0;
  stop.time = 80.0;
  run_engine(s, "ed", {CollisionOutcome::bounce, eps, 1e-9}, stop, &series);

  std::vector<double> t, y, rate;  // rate: omega / sqrt(T) per interval
  std::istringstream rows(series.csv());
  std::string line;
  std::getline(rows, line);
  double e0 = 0, prev_t = 0, prev_e = 0;
  long prev_c = 0;
  while (std::getline(rows, line)) {
    std::vector<double> f;
    std::istringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(std::stod(x));
    const double time = f[0], energy = f[3], collisions = f.back();
    if (t.empty()) e0 = energy;
    else if (time > prev_t)
      rate.push_back(2 * (collisions - prev_c) / (n * (time - prev_t)) / std::sqrt(0.5 * (energy + prev_e) / n));
    t.push_back(time);
    y.push_back(std::sqrt(e0 / energy));
    prev_t = time, prev_e = energy, prev_c = static_cast<long>(collisions);
  }
  ASSERT_GT(t.size(), 30u);
  double mt = 0, my = 0, sxy = 0, sxx = 0, kappa = 0;
  for (std::size_t k = 0; k < t.size(); ++k) mt += t[k] / t.size(), my += y[k] / t.size();
  for (std::size_t k = 0; k < t.size(); ++k) sxy += (t[k] - mt) * (y[k] - my), sxx += (t[k] - mt) * (t[k] - mt);
  for (std::size_t k = 0; k < 5; ++k) kappa += rate[k] / 5;
  const double slope = sxy / sxx;
  for (std::size_t k = 0; k < t.size(); ++k)
    EXPECT_NEAR(y[k], my + slope * (t[k] - mt), 0.01 * y[k]) << "sqrt(E0/E) not linear at t = " << t[k];
  const double predicted = (1 - eps * eps) * kappa * std::sqrt(e0 / n) / 4;
  EXPECT_NEAR(slope / predicted, 1.0, 0.02) << "slope " << slope << ", theory " << predicted;
  EXPECT_GT(y.back(), 2.0);  // the energy fell by more than 4
}

}  // namespace
}  // namespace ballagg
