#pragma once
// The small interface every engine implements: take a state, advance it until a stop
// criterion holds, report what happened to an observer.
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "ballagg/core/state.hpp"

namespace ballagg {

enum class CollisionOutcome { stick, bounce };

struct CollisionSettings {
  CollisionOutcome outcome = CollisionOutcome::stick;
  double restitution = 1.0;  // bounce only, in [0, 1]
  // TC model (Luding & McNamara 1998): a bounce involving a body whose previous collision
  // was less than tc_time ago is elastic. Prevents inelastic collapse (infinitely many
  // collisions in a finite time) from stalling a run. 0 disables it.
  double tc_time = 0.0;
};

struct StopCriteria {
  int clusters = 1;
  double time = std::numeric_limits<double>::infinity();
  double wall_seconds = std::numeric_limits<double>::infinity();
};

enum class StopReason { clusters, time, wall_seconds, no_more_events, no_collision_possible };
std::string_view to_string(StopReason r);

enum class EventKind : std::uint8_t { collision = 0, wall = 1, list_rebuild = 2, time_step = 3 };

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

struct EngineCounters {
  std::int64_t events = 0;           // every event handled, list rebuilds included
  std::int64_t collisions = 0;       // sphere-sphere contacts between different clusters
  std::int64_t merges = 0;           // clusters absorbed (>= sticking collisions: cascades)
  std::int64_t bounces = 0;
  std::int64_t wall_bounces = 0;
  std::int64_t list_rebuilds = 0;
  std::int64_t rebuilt_spheres = 0;    // spheres re-binned by list rebuilds (work measure)
  std::int64_t pair_predictions = 0;   // contact times computed (work measure)
  std::int64_t queue_peak = 0;
  // Time stepping.
  std::int64_t steps = 0;
  std::int64_t minimisations = 0;      // DAHA solves (one per connected group per round)
  std::int64_t daha_iterations = 0;
  std::int64_t placed_at_contact = 0;  // groups not converged in max_iterations, placed at first contact
  std::int64_t link_rounds = 0;        // repetitions of (3.1)-(3.2) beyond the first
  std::int64_t rounds_exhausted = 0;   // steps that reached max_link_rounds
  double max_residual_overlap = 0.0;   // largest relative overlap left after any step
  double max_link_stretch = 0.0;       // largest d / (R_i + R_j) - 1 of an old link after a step
};

struct RunResult {
  StopReason reason = StopReason::clusters;
  EngineCounters counters;
  double wall_seconds = 0.0;
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
  // on_checkpoint (which may end the run by throwing). Keep checkpoint_due cheap.
  virtual bool checkpoint_due() { return false; }
  virtual void on_checkpoint(const State<D>&, const EngineCounters&, const std::string& /*engine_state*/) {}
};

template <int D>
class Engine {
 public:
  virtual ~Engine() = default;
  virtual std::string_view name() const = 0;
  virtual RunResult run(State<D>& state, const StopCriteria& stop, RunObserver<D>& observer) = 0;

  // The checkpoint contract (docs/checkpoints.md). An engine that supports checkpoints
  // (1) polls observer.checkpoint_due() during run() at points between events or steps and
  // hands on_checkpoint bytes that hold everything it carries forward (counters included;
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
