#pragma once
// ballagg.Simulation: a state and its engine, run from Python with a callback (every k
// events, or at every multiple of a simulated time interval) and, optionally, the output
// files of `ballagg run` (trajectories, timeseries.csv) written as it runs.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "convert.hpp"

#include "ballagg/engines/engine.hpp"
#include "ballagg/io/frame.hpp"
#include "ballagg/run/simulation.hpp"

namespace ballagg::python {

// The callback returned False: the run ends at the call (after an event, or at a time).
struct StoppedByCallback {
  double time = std::numeric_limits<double>::quiet_NaN();  // a timed call's time; NaN after an event
};

// When the callback is called: after every `events` events (time steps for ts), or at
// every t = k * every_time of simulated time (0: not timed).
struct CallbackSchedule {
  std::int64_t events = 1;
  double every_time = 0.0;
  bool timed() const { return every_time > 0.0; }
};

// What a run writes besides the state: the trajectory files and timeseries.csv of
// `ballagg run` (out: their directory; none: nothing written).
struct RunOutputRequest {
  std::optional<std::string> out;
  bool overwrite = false;
};

// The time a callback looks at: the state's own time, or, inside a timed call, the
// multiple of every_time it is called for (positions are exact at any time up to the next
// event, as for the trajectory frames of run/snapshots.hpp).
struct ViewTime {
  double time = std::numeric_limits<double>::quiet_NaN();
  bool active() const { return !std::isnan(time); }
};

template <int D>
class Simulation {
 public:
  explicit Simulation(const Config& given);
  Simulation(const Config& given, State<D> initial);

  py::dict run(const py::object& self, const py::object& callback, const CallbackSchedule& when,
               const StopCriteria& stop, const RunOutputRequest& output);

  // The state as a callback sees it (at the view time inside a timed call).
  double time() const { return view_.active() ? view_.time : state_.time; }
  Frame<D> frame() const;
  // A copy of the state at the view time inside a timed call, else the state itself.
  State<D> state_now() const;
  const State<D>& state() const { return state_; }
  const Config& config() const { return config_; }
  std::string_view engine() const { return engine_->name(); }
  bool running() const { return running_; }

 private:
  RunResult run_engine(const py::object& self, const py::object& callback, const CallbackSchedule& when,
                       StopCriteria stop, const RunOutputRequest& output);

  State<D> state_;
  Config config_;
  std::unique_ptr<Engine<D>> engine_;
  ViewTime view_;
  EngineCounters last_counters_;  // of a run the callback ended
  bool running_ = false;  // inside run(): the callback may read the state, not run it
};

// The stop criteria of the configuration, with run()'s arguments (checked as the
// configuration's [stop] keys are) in place of the ones given.
StopCriteria stop_criteria_with(const Config& c, std::optional<std::int64_t> clusters, std::optional<double> time,
                                std::optional<double> wall_seconds);

}  // namespace ballagg::python
