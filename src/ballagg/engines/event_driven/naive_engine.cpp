// The paper's plain event-driven method (Appendix A), kept deliberately simple: before
// every event, the contact time (A.3) of every pair of spheres in different clusters and
// the wall time of every cluster are recomputed, and the earliest is handled. O(N^2) per
// event; the reference against which the fast engine is tested.
#include <optional>

#include "ballagg/collision/prediction.hpp"
#include "ballagg/collision/resolve.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/engines/event_driven/event_driven_counters.hpp"
#include "ballagg/engines/event_driven/event_driven_engine.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"

namespace ballagg {
namespace {

// The loop reads the clock and the signal flag every kEventsPerClockCheck events; one
// event here costs N^2 / 2 contact predictions (about 10 ns each), so from this many spheres
// 256 events take a second or more (N = 10^5: hours) and the search itself asks the run's
// guard, once per sphere's row of pairs. Below it the loop's rhythm answers within a second.
inline constexpr int kGuardedSearchSpheres = 512;

template <int D>
class NaiveCore {
 public:
  using Settings = EventDrivenSettings;
  NaiveCore(State<D>& state, const EventDrivenSettings& settings) : s_(state), law_(settings.collision) {
    keep_what_the_law_reads(s_, law_);
  }
  // Everything it keeps between events is its counters: it predicts from scratch.
  NaiveCore(State<D>& state, const EventDrivenSettings& settings, std::string_view saved)
      : s_(state), law_(settings.collision) {
    keep_what_the_law_reads(s_, law_);
    ByteReader r(saved, "checkpoint of the ed-naive engine");
    count_.restore(r);
    loop_ = r.get<EventLoopState>("loop state");
    r.expect_end();
  }

  EventDrivenCounters& counters() { return count_; }
  EventLoopState& loop() { return loop_; }
  void save(ByteWriter& w) const {
    count_.save(w);
    w.put(loop_);
  }

  // Nothing when `guard` stops the run during the search (from kGuardedSearchSpheres on):
  // the core predicts from scratch, so the loop may end the run or write its checkpoint
  // there, and the predictions of the search given up are not counted.
  std::optional<Event> next_event(RunGuard& guard) {
    std::optional<Event> best;
    auto consider = [&](const Event& e) {
      if (e.time < kNever && (!best || later(*best, e))) best = e;
    };
    const int n = s_.n_spheres();
    const bool guarded = n >= kGuardedSearchSpheres;
    const std::int32_t* cluster = s_.spheres.cluster.data();
    std::int64_t predictions = 0;
    for (int i = 0; i < n; ++i) {
      if (guarded && guard.poll()) return std::nullopt;
      for (int j = i + 1; j < n; ++j)
        if (cluster[i] != cluster[j]) {
          const double earliest = best ? best->time : kNever;
          consider({predicted_contact(s_, i, j, s_.time, earliest, earliest), i, j, 0, 0, EventKind::collision});
          ++predictions;
        }
    }
    count_.pair_predictions += predictions;
    for (int c : s_.alive_clusters()) {
      const WallContact w = next_wall_contact(s_, c);
      consider({w.time, c, w.axis, 0, 0, EventKind::wall});
    }
    return best;
  }

  EventRecord handle(const Event& e) {
    const double t = e.time;
    if (e.kind == EventKind::wall) {
      reflect_cluster(s_, e.a, e.b, t);
      ++count_.wall_bounces;
      return {.time = t, .kind = EventKind::wall, .cluster = e.a, .axis = e.b};
    }
    ++count_.collisions;
    EventRecord r{.time = t, .kind = EventKind::collision, .sphere_i = e.a, .sphere_j = e.b};
    if (law_.outcome == CollisionOutcome::bounce) {
      r.cluster = s_.spheres.cluster[e.a];
      bounce_clusters(s_, e.a, e.b, t, law_);
      ++count_.bounces;
      return r;
    }
    int keep = s_.merge(e.a, e.b, t);
    ++r.merges;
    while (auto pair = touching_pair(keep, t)) {
      keep = s_.merge(pair->first, pair->second, t);
      ++r.merges;
    }
    count_.merges += r.merges;
    r.cluster = keep;
    return r;
  }

 private:
  std::optional<std::pair<int, int>> touching_pair(int c, double t) const {
    const int n = s_.n_spheres();
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        const int ci = s_.spheres.cluster[i], cj = s_.spheres.cluster[j];
        if (ci != cj && (ci == c || cj == c) && touching(s_, i, j, t)) return std::pair{i, j};
      }
    }
    return std::nullopt;
  }

  State<D>& s_;
  CollisionSettings law_;
  EventDrivenCounters count_;
  EventLoopState loop_;
};

}  // namespace

template <int D>
std::unique_ptr<Engine<D>> make_naive_event_driven_engine(const EventDrivenSettings& settings) {
  return std::make_unique<EventLoopEngine<D, NaiveCore<D>>>("ed-naive", settings);
}

template std::unique_ptr<Engine<2>> make_naive_event_driven_engine<2>(const EventDrivenSettings&);
template std::unique_ptr<Engine<3>> make_naive_event_driven_engine<3>(const EventDrivenSettings&);

}  // namespace ballagg
