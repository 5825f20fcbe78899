#pragma once
// The small interface every engine implements: take a state, advance it until a stop
// criterion holds, report what happened to an observer.
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "ballagg/collision/collision_settings.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/run_guard.hpp"
#include "ballagg/core/state.hpp"
#include "ballagg/engines/engine_counters.hpp"

namespace ballagg {

struct StopCriteria {
  int clusters = 1;
  double time = std::numeric_limits<double>::infinity();
  double wall_seconds = std::numeric_limits<double>::infinity();
  // Rigid-body engine: stop once this fraction of the mass is in bodies of two or more
  // spheres (or merged spheres); above 1: never.
  double aggregated_fraction = std::numeric_limits<double>::infinity();
  // The run's guard (core/run_guard.hpp), shared with the recorders that poll it; its clock
  // then bounds the run instead of wall_seconds. Null: the engine keeps its own, from
  // wall_seconds.
  RunGuard* guard = nullptr;
};

// aggregated: stop.aggregated_fraction reached; body_spans_box: a rigid body became as
// large as the periodic box and could touch its own image (rigid-body engine);
// output_limit: a recorder reached its row or frame cap (docs/hardening.md); interrupted:
// a signal, and no observer wrote a checkpoint and ended the run (the caller then ends
// it without its normal files).
enum class StopReason {
  clusters, time, wall_seconds, no_more_events, no_collision_possible, aggregated, body_spans_box, output_limit,
  interrupted
};
// The reason a run stopped by its guard gives.
StopReason stop_reason_of(StopCause cause);
std::string_view to_string(StopReason r);

// contact_search: the rigid-body engine resumes the search for the first contact of two
// rotating bodies (or of a rotating body and a wall) at this time.
enum class EventKind : std::uint8_t {
  collision = 0, wall = 1, list_rebuild = 2, time_step = 3, contact_search = 4
};

// What the engine tells an observer after each event it handled.
struct EventRecord {
  double time = 0.0;
  EventKind kind = EventKind::collision;
  int sphere_i = -1, sphere_j = -1;  // collision: the touching spheres (i < j)
  int cluster = -1;                  // surviving / reflected / rebuilt cluster
  int axis = -1;                     // wall: the axis of the wall's normal
  int merges = 0;                    // clusters absorbed by this event (cascade included)
                                     // (time step: by the whole step)
};

struct RunResult {
  StopReason reason = StopReason::clusters;
  EngineCounters counters;     // what every engine counts
  EngineCounts engine_counts;  // the engine's own counters, in the order summary.json lists them
  double wall_seconds = 0.0;
  // One of engine_counts (throws std::out_of_range when the engine has none of that name).
  std::int64_t count(std::string_view key) const { return engine_count<std::int64_t>(engine_counts, key); }
  double measure(std::string_view key) const { return engine_count<double>(engine_counts, key); }
};

template <int D>
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  virtual void on_start(const State<D>&) {}
  // Called before the state is advanced to an event at time t (t >= state.time).
  virtual void before_event(const State<D>&, double /*t*/) {}
  virtual void after_event(const State<D>&, const EventRecord&, const EngineCounters&) {}
  virtual void on_finish(const State<D>&, const RunResult&) {}

  // Checkpoints (docs/checkpoints.md). An engine that supports them asks checkpoint_due()
  // at points between two events (or steps) where everything it carries from one to the
  // next can be saved; when it returns true, the engine hands that saved state to
  // on_checkpoint_stream (which may end the run by throwing). Keep checkpoint_due cheap.
  // An observer that combines others hands the checkpoint only to those that ask for it
  // (ObserverList), so that none gathers bytes it does not use.
  virtual bool checkpoint_due() { return false; }
  // save(w) puts the engine's state into w. An observer that writes a checkpoint file
  // streams it there: at a few hundred bytes per sphere it is never held whole. The
  // default gathers the bytes and hands them to on_checkpoint.
  using EngineSave = std::function<void(ByteWriter&)>;
  virtual void on_checkpoint_stream(const State<D>& s, const EngineCounters& c, const EngineSave& save) {
    ByteWriter w;
    save(w);
    on_checkpoint(s, c, w.bytes());
  }
  virtual void on_checkpoint(const State<D>&, const EngineCounters&, const std::string& /*engine_state*/) {}

  // Engines whose clusters only translate keep State::position exact at every time. The
  // rigid-body engine rotates clusters and writes the spheres' offsets into the state
  // only when asked: at on_start, on_finish, and at the time returned here, the next time
  // this observer will read sphere positions (or the clusters' angular velocities) between
  // events. Before calling before_event(s, t) with t past that time, it brings the state
  // to exactly that time and calls before_event(s, just after it) first; an after_event
  // call finds the state exact if this is <= s.time. An observer that reads only cluster
  // totals (counts, energies, momenta) keeps the default: never.
  virtual double next_position_read() const { return std::numeric_limits<double>::infinity(); }
};

template <int D>
class Engine {
 public:
  virtual ~Engine() = default;
  virtual std::string_view name() const = 0;
  virtual RunResult run(State<D>& state, const StopCriteria& stop, RunObserver<D>& observer) = 0;

  // The checkpoint contract (docs/checkpoints.md). An engine that supports checkpoints
  // (1) polls observer.checkpoint_due() during run() at points between events or steps and
  // hands on_checkpoint_stream bytes that hold everything it carries forward (counters included;
  // the State is saved by the caller), and (2) implements resume_from: given the State
  // restored from the same checkpoint and those bytes, it prepares itself so that the
  // next run(state, ...) on that same State object continues exactly as the saved run
  // would have, bit for bit (observer.on_start is still called). resume_from throws
  // CheckpointError for bytes it did not write, and never reads out of bounds.
  virtual bool supports_checkpoints() const { return false; }
  virtual void resume_from(State<D>& /*state*/, std::string_view /*engine_state*/) {
    throw std::logic_error(std::string(name()) + " cannot resume from a checkpoint");
  }
};

}  // namespace ballagg
