#pragma once
// The main loop shared by the event-driven engines: take the next event, check the stop
// criteria, advance, handle, report. `Core` supplies next_event() and handle(); the fast
// engine and the naive reference differ only in how they find the next event.
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include <fmt/format.h>

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

// What the loop carries from one event to the next besides the core's own state (saved
// with it in a checkpoint).
struct EventLoopState {
  std::int64_t last_collision_event = 0;  // events handled when the last collision was
};

// Reading the clock (stop.wall_seconds) and the signal flag, and offering a checkpoint,
// cost ~20 ns: doing it every this many events keeps it invisible. A run stops within this
// many events of its wall-clock limit or of a signal.
inline constexpr std::int64_t kEventsPerClockCheck = 256;

// Events at one instant are legitimate (a lattice start, a contact cascade, a chain of
// inelastic bounces converging), but a few per sphere, far below these. More means the
// intervals between events have fallen below the resolution of the simulated time (a
// time t is resolved to 2.2e-16 t: docs/hardening.md), as in an inelastic collapse
// without the TC model. A run with a wall-clock limit waits for it (the user said how
// long); one without stops with an error instead of handling events at that instant for
// ever.
inline constexpr std::int64_t kMaxEventsAtInstantPerSphere = 1000;
inline constexpr std::int64_t kMaxEventsAtInstantFloor = 1'000'000;

// A core whose search for the next event is long (ed-naive: O(N^2)) may take the guard,
// next_event(RunGuard&), and return nothing once it says stop; the loop then stops as
// between two events.
template <class Core>
std::optional<Event> next_event_of(Core& core, RunGuard& guard) {
  if constexpr (requires { core.next_event(guard); }) return core.next_event(guard);
  else return core.next_event();
}

// `Core` may also supply stop_reason() (criteria of its own), for checkpoints loop() (an
// EventLoopState) and save(ByteWriter&): puts its whole state, taken between two events, and
// put_back(event): files the event next_event() returned again, unhandled (a core that
// predicts from scratch, ed-naive, finds it again by itself).
//
// The observers' work before an event (rows and frames due before it) polls the run's
// guard and may be cut short (RunGuard). The loop then does not handle the event: on a
// signal it puts the event back, so that the checkpoint taken next resumes exactly where
// the observers stopped; on the wall-clock limit or an output cap it ends the run at the
// event's time, without the output that had no time to be written.
template <int D, class Core>
RunResult run_event_loop(Core& core, State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) {
  RunGuard own_guard(stop.wall_seconds);
  RunGuard& guard = stop.guard != nullptr ? *stop.guard : own_guard;
  // After this many events without a collision, check whether one is possible at all.
  const std::int64_t quiet_limit = 16 * static_cast<std::int64_t>(s.n_spheres()) + 4096;
  const std::int64_t instant_limit =
      kMaxEventsAtInstantPerSphere * static_cast<std::int64_t>(s.n_spheres()) + kMaxEventsAtInstantFloor;
  std::int64_t events_at_instant = 0;

  RunResult result;
  EngineCounters& count = core.counters();
  observer.on_start(s);
  EventLoopState own_loop;  // for a core without checkpoints (no loop() of its own)
  std::int64_t& last_collision_event = [&]() -> std::int64_t& {
    if constexpr (requires { core.loop(); }) return core.loop().last_collision_event;
    else return own_loop.last_collision_event;
  }();
  while (true) {
    if (s.n_clusters() <= stop.clusters) { result.reason = StopReason::clusters; break; }
    if constexpr (requires { core.stop_reason(); }) {  // criteria only some engines know
      if (const std::optional<StopReason> r = core.stop_reason()) { result.reason = *r; break; }
    }
    if (count.events % kEventsPerClockCheck == 0 || guard.stopped()) {
      guard.check();
      if (guard.cause() == StopCause::wall_seconds) { result.reason = StopReason::wall_seconds; break; }
      // A signal: the checkpointing observer writes one and ends the run by throwing.
      if constexpr (requires(ByteWriter& w) { core.save(w); })
        if (observer.checkpoint_due()) observer.on_checkpoint_stream(s, count, [&](ByteWriter& w) { core.save(w); });
      if (guard.stopped()) { result.reason = stop_reason_of(guard.cause()); break; }
    }
    if (count.events - last_collision_event > quiet_limit) {
      if (collisions_impossible(s)) { result.reason = StopReason::no_collision_possible; break; }
      last_collision_event = count.events;
    }
    const std::optional<Event> next = next_event_of(core, guard);
    if (guard.stopped()) continue;  // the search was cut short: the checks above end the run
    // The time the observers are told of next: the event's, or the end of the run.
    const double until = !next ? stop.time : std::min(next->time, stop.time);
    if (until < kNever) {
      observer.before_event(s, until);
      if (guard.stopped()) {  // the observers' output was cut short
        if (guard.cause() == StopCause::signal) {
          if constexpr (requires { core.put_back(*next); })
            if (next) core.put_back(*next);
          continue;
        }
        result.reason = stop_reason_of(guard.cause());
        s.time = std::max(s.time, until);
        break;
      }
    }
    if (!next) {
      result.reason = collisions_impossible(s) ? StopReason::no_collision_possible : StopReason::no_more_events;
      if (stop.time < kNever) s.time = stop.time;
      break;
    }
    if (next->time > stop.time) {
      result.reason = StopReason::time;
      s.time = stop.time;
      break;
    }
    if (next->time > s.time) {
      events_at_instant = 0;
    } else if (++events_at_instant > instant_limit && stop.wall_seconds == kNever) {
      throw std::runtime_error(fmt::format("the simulated time stopped advancing at t = {}: {} events at that instant "
                                           "(the intervals between events are below the resolution of the time)",
                                           s.time, events_at_instant));
    }
    s.time = std::max(s.time, next->time);
    const EventRecord record = core.handle(*next);
    ++count.events;
    if (record.kind == EventKind::collision) last_collision_event = count.events;
    observer.after_event(s, record, count);
  }
  result.counters = count;
  if constexpr (requires { core.counters().report(); }) result.engine_counts = core.counters().report();
  result.wall_seconds = guard.elapsed();
  observer.on_finish(s, result);
  return result;
}

// Runs a core: by its own run() if it has one (the rigid-body engine wraps the observer and
// the loop), else by run_event_loop.
template <int D, class Core>
RunResult run_core(Core& core, State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) {
  if constexpr (requires { core.run(s, stop, observer); }) return core.run(s, stop, observer);
  else return run_event_loop(core, s, stop, observer);
}

// An engine made of a Core run by run_core (ed, ed-naive, rigid-body), with checkpoints: the
// core is built from the state when run() starts, or restored by resume_from() from the
// bytes its save(ByteWriter&) put (Core(State&, const Settings&, std::string_view saved), which
// throws CheckpointError for bytes that do not fit the state).
template <int D, class Core>
class EventLoopEngine final : public Engine<D> {
 public:
  using Settings = typename Core::Settings;
  EventLoopEngine(std::string_view name, const Settings& settings) : name_(name), settings_(settings) {}
  std::string_view name() const override { return name_; }
  bool supports_checkpoints() const override { return true; }
  void resume_from(State<D>& s, std::string_view saved) override {
    resumed_.reset();
    resumed_.emplace(s, settings_, saved);
    resumed_state_ = &s;
  }
  RunResult run(State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) override {
    if (!resumed_) {
      Core core(s, settings_);
      return run_core(core, s, stop, observer);
    }
    if (resumed_state_ != &s) throw std::logic_error("a resumed engine must run the state it was resumed with");
    const RunResult r = run_core(*resumed_, s, stop, observer);
    resumed_.reset();
    return r;
  }

 private:
  std::string_view name_;
  Settings settings_;
  std::optional<Core> resumed_;
  const State<D>* resumed_state_ = nullptr;
};

}  // namespace ballagg
