#pragma once
// The main loop shared by the event-driven engines: take the next event, check the stop
// criteria, advance, handle, report. `Core` supplies next_event() and handle(); the fast
// engine and the naive reference differ only in how they find the next event.
#include <chrono>
#include <optional>

#include "ballagg/core/state.hpp"
#include "ballagg/engines/engine.hpp"
#include "ballagg/collision/contact_time.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"

namespace ballagg {

// True when no two clusters can ever meet again: all move with the same velocity in a
// periodic box (or all are at rest), and none spins. Walls change velocities, so there
// only rest counts.
template <int D>
bool collisions_impossible(const State<D>& s) {
  const Vec<D>* first = nullptr;
  for (int c : s.alive_clusters()) {
    const Cluster<D>& k = s.clusters[c];
    if (!s.spin.empty() && k.size() > 1 && s.spin[c].angular_momentum != Spin<D>::Zero()) return false;
    if (!s.box.periodic() && k.velocity != Vec<D>::Zero()) return false;
    if (first == nullptr) first = &k.velocity;
    else if (k.velocity != *first) return false;
  }
  return true;
}

template <int D, class Core>
RunResult run_event_loop(Core& core, State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) {
  using clock = std::chrono::steady_clock;
  const auto started = clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(clock::now() - started).count(); };
  // Checking the clock costs ~20 ns; doing it every 256 events keeps it invisible.
  constexpr std::int64_t kClockEvery = 256;
  // After this many events without a collision, check whether one is possible at all.
  const std::int64_t quiet_limit = 16 * static_cast<std::int64_t>(s.n_spheres()) + 4096;

  RunResult result;
  EngineCounters& count = core.counters();
  observer.on_start(s);
  std::int64_t last_collision_event = 0;
  while (true) {
    if (s.n_clusters() <= stop.clusters) { result.reason = StopReason::clusters; break; }
    if constexpr (requires { core.stop_reason(); }) {  // criteria only some engines know
      if (const std::optional<StopReason> r = core.stop_reason()) { result.reason = *r; break; }
    }
    if (count.events % kClockEvery == 0 && elapsed() >= stop.wall_seconds) {
      result.reason = StopReason::wall_seconds;
      break;
    }
    if (count.events - last_collision_event > quiet_limit) {
      if (collisions_impossible(s)) { result.reason = StopReason::no_collision_possible; break; }
      last_collision_event = count.events;
    }
    const std::optional<Event> next = core.next_event();
    if (!next) {
      result.reason = collisions_impossible(s) ? StopReason::no_collision_possible : StopReason::no_more_events;
      if (stop.time < kNever) { observer.before_event(s, stop.time); s.time = stop.time; }
      break;
    }
    if (next->time > stop.time) {
      result.reason = StopReason::time;
      observer.before_event(s, stop.time);
      s.time = stop.time;
      break;
    }
    observer.before_event(s, next->time);
    s.time = std::max(s.time, next->time);
    const EventRecord record = core.handle(*next);
    ++count.events;
    if (record.kind == EventKind::collision) last_collision_event = count.events;
    observer.after_event(s, record, count);
  }
  result.counters = count;
  result.wall_seconds = elapsed();
  observer.on_finish(s, result);
  return result;
}

}  // namespace ballagg
