#pragma once
// Helpers shared by the tests: small hand-built states, runs with an observer that records
// every event, and exhaustive checks of the physics invariants.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <functional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/config/config.hpp"
#include "ballagg/engines/event_driven/event_driven_engine.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/io/timeseries.hpp"
#include "ballagg/run/simulation.hpp"

// Checks that `needle` occurs in `haystack`, printing both when it does not.
#define EXPECT_CONTAINS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << "'" << (needle) << "' not in: " << (haystack)

namespace ballagg::testing {

// A fresh directory under the system's temporary directory, removed with its content.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "ballagg-test-") {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / (prefix + std::to_string(rd()) + "-" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  // Writes `text` to the file `name` in the directory and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

 private:
  std::filesystem::path path_;
};

// A sphere of a hand-built state; spheres with the same cluster label >= 0 are glued.
template <int D>
struct Ball {
  Vec<D> x;
  Vec<D> v;
  double radius = 0.5;
  double mass = 1.0;
  std::int64_t cluster = -1;
};

template <int D>
State<D> make_state(double box_length, Boundary boundary, const std::vector<Ball<D>>& balls) {
  SphereTable<D> t;
  bool glued = false;
  for (const Ball<D>& b : balls) glued = glued || b.cluster >= 0;
  for (std::size_t k = 0; k < balls.size(); ++k) {
    t.position.push_back(balls[k].x);
    t.velocity.push_back(balls[k].v);
    t.radius.push_back(balls[k].radius);
    t.mass.push_back(balls[k].mass);
    if (glued) t.cluster.push_back(balls[k].cluster >= 0 ? balls[k].cluster : 1'000'000 + static_cast<int>(k));
  }
  return assemble_state(Box<D>{box_length, boundary}, t);
}

template <int D>
Vec<D> vec(double x, double y, double z = 0.0) {
  Vec<D> v;
  if constexpr (D == 2) v << x, y;
  else v << x, y, z;
  return v;
}

// Records every event and runs an optional check after each one.
template <int D>
class Recorder final : public RunObserver<D> {
 public:
  std::vector<EventRecord> events;
  std::function<void(const State<D>&, const EventRecord&)> check;

  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters&) override {
    events.push_back(e);
    if (check) check(s, e);
  }
  std::vector<EventRecord> of_kind(EventKind k) const {
    std::vector<EventRecord> out;
    for (const EventRecord& e : events)
      if (e.kind == k) out.push_back(e);
    return out;
  }
};

template <int D>
RunResult run_engine(State<D>& s, const std::string& engine, const CollisionSettings& law = {},
                     const StopCriteria& stop = {}, std::type_identity_t<RunObserver<D>>* observer = nullptr) {
  RunObserver<D> none;
  auto e = engine == "ed" ? make_event_driven_engine<D>({law, std::nullopt}) : make_naive_event_driven_engine<D>({law, std::nullopt});
  return e->run(s, stop, observer ? *observer : none);
}

// Largest relative overlap over all pairs (O(N^2)): (sigma - d) / sigma = 1 - d / sigma,
// largest where (d / sigma)^2 is smallest. Called after every event by the invariant
// tests: the positions are computed once, and no square root per pair.
template <int D>
double worst_overlap(const State<D>& s) {
  std::vector<Vec<D>> x(s.n_spheres());
  for (int i = 0; i < s.n_spheres(); ++i) x[i] = s.unwrapped_position(i, s.time);
  double closest = 1e300;  // min (d / sigma)^2
  for (int i = 0; i < s.n_spheres(); ++i) {
    for (int j = i + 1; j < s.n_spheres(); ++j) {
      const double sigma = s.spheres.radius[i] + s.spheres.radius[j];
      closest = std::min(closest, s.box.separation(x[i], x[j]).squaredNorm() / (sigma * sigma));
    }
  }
  return s.n_spheres() < 2 ? -1e300 : 1.0 - std::sqrt(closest);
}

// A sphere that turns back towards its bin while a partner rebuilds its lists: the case
// where judging a pair by the spheres' present places, not by their bins, misses a
// collision (engines/event_driven/neighbor_keeper.hpp). Walls, L = 10, radius 0.5, and a
// skin of kTurningSkin (lists expire at a drift of 0.5):
//   sphere 0 starts at x = 0.95 moving at -1: it bounces off the wall x = 0 at t = 0.45,
//     0.45 from its bin, and turns back; its drift reaches 0.5 only at t = 1.4;
//   sphere 1 starts at x = 3.225 moving at -0.8: its lists expire at t = 0.625, when the
//     two are 2.05 apart (beyond sigma + skin = 2) but their bins only 1.775.
// They touch when 3.175 - 1.8 t = 1: kTurningContact, before either rebuilds again
// (sphere 1 at t = 1.25).
inline constexpr double kTurningSkin = 1.0;
inline constexpr double kTurningContact = 2.175 / 1.8;
template <int D>
State<D> turning_sphere_and_rebuilt_partner() {
  return make_state<D>(10, Boundary::walls,
                       {{vec<D>(0.95, 5, 5), vec<D>(-1, 0, 0)}, {vec<D>(3.225, 5, 5), vec<D>(-0.8, 0, 0)}});
}

// A config for a small random system.
inline Config small_config(int dimension, int n, double volume_fraction, Boundary boundary, std::uint64_t seed) {
  Config c;
  c.system.dimension = dimension;
  c.system.n = n;
  c.system.volume_fraction = volume_fraction;
  c.system.boundary = boundary;
  c.system.radius = 0.5;
  c.initial.positions = InitialPositions::random;
  c.initial.seed = seed;
  return c;
}

}  // namespace ballagg::testing
