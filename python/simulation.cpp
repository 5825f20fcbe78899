#include "simulation.hpp"

#include <filesystem>
#include <stdexcept>

#include "ballagg/core/finite_state.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/timeseries.hpp"
#include "ballagg/run/observer_list.hpp"
#include "ballagg/run/run_files.hpp"
#include "ballagg/run/snapshots.hpp"

namespace ballagg::python {
namespace {

// The Python callback, around the run's recorders (`recorders`: the output files). Before
// an event it is called first, so that a run it ends at a time t still gets every frame
// and row before t (Simulation::run_engine gives them); after an event it is called last,
// when the recorders have seen the event.
template <int D>
class PythonObserver final : public RunObserver<D> {
 public:
  PythonObserver(py::object callback, const CallbackSchedule& when, py::object self, ViewTime& view,
                 RunObserver<D>& recorders)
      : callback_(std::move(callback)), when_(when), self_(std::move(self)), view_(view), recorders_(recorders) {}

  void on_start(const State<D>& s) override {
    if (when_.timed()) next_k_ = static_cast<std::int64_t>(std::floor(s.time / when_.every_time)) + 1;
    recorders_.on_start(s);
  }
  void before_event(const State<D>& s, double t) override {
    if (timed())
      for (; next_time() < t; ++next_k_)
        if (next_time() >= s.time) call_at(next_time(), true);
    recorders_.before_event(s, t);
  }
  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters& c) override {
    last_ = c;
    recorders_.after_event(s, e, c);
    if (!callback_.is_none() && !when_.timed() && ++calls_ % when_.events == 0) {
      const py::object r = callback_(self_);
      if (py::isinstance<py::bool_>(r) && !r.cast<bool>()) throw StoppedByCallback{};
    }
    // Ctrl-C (KeyboardInterrupt) after any event: a flag test, nanoseconds.
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }
  void on_finish(const State<D>& s, const RunResult& r) override {
    last_ = r.counters;
    recorders_.on_finish(s, r);
    // The multiples of every_time up to the end (the end included): the run is over, so a
    // False returned here ends nothing.
    if (timed())
      for (; next_time() <= s.time; ++next_k_) call_at(next_time(), false);
  }
  // The rigid-body engine rotates the spheres into the state for the calls (and frames).
  double next_position_read() const override {
    double own = std::numeric_limits<double>::infinity();
    if (timed()) own = next_time();
    else if (!callback_.is_none() && (calls_ + 1) % when_.events == 0) own = -std::numeric_limits<double>::infinity();
    return std::min(own, recorders_.next_position_read());
  }
  const EngineCounters& last() const { return last_; }

 private:
  bool timed() const { return when_.timed() && !callback_.is_none(); }
  double next_time() const { return static_cast<double>(next_k_) * when_.every_time; }
  void call_at(double t, bool may_stop) {
    view_.time = t;
    const py::object r = callback_(self_);
    view_ = ViewTime{};
    if (may_stop && py::isinstance<py::bool_>(r) && !r.cast<bool>()) throw StoppedByCallback{t};
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }

  py::object callback_;
  CallbackSchedule when_;
  py::object self_;
  ViewTime& view_;
  RunObserver<D>& recorders_;
  std::int64_t calls_ = 0;
  std::int64_t next_k_ = 1;
  EngineCounters last_;
};

// The output files of `ballagg run` that a Simulation writes while it runs: trajectories
// (output.snapshot_every, output.snapshot_formats) and timeseries.csv, into a directory
// opened as `ballagg run` opens one (refused if it holds another run, unless overwrite).
template <int D>
class RunOutput {
 public:
  RunOutput(const Config& c, const State<D>& s, const StopCriteria& stop, const RunOutputRequest& request)
      : dir_(*request.out), guard_(stop.wall_seconds),
        timeseries_(c.output.timeseries_interval, c.engine.kind == EngineKind::rigid_body, &guard_) {
    check_timeseries_rows(c.output.timeseries_interval, s.time, stop.time);
    check_snapshot_frames(c.output.snapshot_every, s.time, stop.time);
    directory_.emplace(open_new_run_directory(dir_, request.overwrite));
    snapshots_ = make_snapshot_recorder(c, s, dir_, std::nullopt, &guard_);
    recorders_.add(&timeseries_);
    if (snapshots_) recorders_.add(snapshots_.get());
  }
  RunGuard& guard() { return guard_; }
  ObserverList<D>& recorders() { return recorders_; }
  void write_timeseries() const { write_file_atomically(dir_, "timeseries.csv", timeseries_.csv()); }
  // After an error: nothing of the run stays (the trajectories' temporary files go with
  // their writer; a directory this run created goes too).
  void abandon() {
    snapshots_.reset();
    const bool created = directory_ && directory_->created;
    directory_.reset();
    std::error_code ec;
    if (created) std::filesystem::remove_all(dir_, ec);
  }

 private:
  std::string dir_;
  RunGuard guard_;
  TimeseriesRecorder<D> timeseries_;
  std::optional<NewRunDirectory> directory_;
  std::unique_ptr<SnapshotRecorder<D>> snapshots_;
  ObserverList<D> recorders_;
};

py::dict result_dict(std::string_view reason, const EngineCounters& n, double seconds) {
  py::dict d;
  d["stop_reason"] = reason;
  d["events"] = n.events;
  d["collisions"] = n.collisions;
  d["merges"] = n.merges;
  d["bounces"] = n.bounces;
  d["wall_bounces"] = n.wall_bounces;
  d["steps"] = n.steps;
  d["wall_seconds"] = seconds;
  return d;
}

}  // namespace

StopCriteria stop_criteria_with(const Config& c, std::optional<std::int64_t> clusters, std::optional<double> time,
                                std::optional<double> wall_seconds) {
  StopCriteria stop = stop_criteria(c);
  // The checks of the configuration's [stop] keys, with the same words.
  if (clusters) {
    check_stop_clusters(*clusters, "Simulation.run argument clusters");
    stop.clusters = static_cast<int>(std::min<std::int64_t>(*clusters, std::numeric_limits<int>::max()));
  }
  if (time) {
    check_stop_duration(*time, "Simulation.run argument time");
    stop.time = *time;
  }
  if (wall_seconds) {
    check_stop_duration(*wall_seconds, "Simulation.run argument wall_seconds");
    stop.wall_seconds = *wall_seconds;
  }
  return stop;
}

template <int D>
Simulation<D>::Simulation(const Config& given)
    : state_(make_initial_state<D>(given)), config_(resolve_defaults(given, state_)), engine_(make_engine<D>(config_)) {}

template <int D>
Simulation<D>::Simulation(const Config& given, State<D> initial)
    : state_(std::move(initial)), config_(resolve_defaults(given, state_)), engine_(make_engine<D>(config_)) {}

template <int D>
Frame<D> Simulation<D>::frame() const {
  if (!view_.active() || view_.time == state_.time) return capture_frame(state_, state_.time, 0);
  // As a trajectory frame between two steps of the time-stepping engine (run/snapshots.hpp).
  return capture_frame(state_, view_.time, 0, config_.engine.kind == EngineKind::ts);
}

template <int D>
State<D> Simulation<D>::state_now() const {
  State<D> s = state_;
  s.time = time();  // positions are lazy: exact at any time up to the next event
  return s;
}

template <int D>
py::dict Simulation<D>::run(const py::object& self, const py::object& callback, const CallbackSchedule& when,
                            const StopCriteria& stop, const RunOutputRequest& output) {
  // The engine is in the middle of an event while the callback runs: a second run from
  // there would work on a state and a calendar that the first one still holds.
  if (running_)
    throw std::runtime_error("Simulation.run called while the simulation runs (from its callback): return False from "
                             "the callback to end the run, then call run() again");
  struct Running {
    bool& flag;
    explicit Running(bool& f) : flag(f) { flag = true; }
    ~Running() { flag = false; }
  } running(running_);
  try {
    const RunResult r = run_engine(self, callback, when, stop, output);
    return result_dict(to_string(r.reason), r.counters, r.wall_seconds);
  } catch (const StoppedByCallback&) {
    return result_dict("callback", last_counters_, 0.0);
  }
}

template <int D>
RunResult Simulation<D>::run_engine(const py::object& self, const py::object& callback, const CallbackSchedule& when,
                                    StopCriteria stop, const RunOutputRequest& output) {
  std::optional<RunOutput<D>> files;
  ObserverList<D> no_recorders;
  if (output.out) {
    files.emplace(config_, state_, stop, output);
    stop.guard = &files->guard();
    files->guard().start_clock();
  }
  PythonObserver<D> observer(callback, when, self, view_, files ? files->recorders() : no_recorders);
  try {
    const RunResult r = engine_->run(state_, stop, observer);
    throw_if_not_finite(state_, engine_->name(), first_non_finite(state_));  // no NaN handed back
    if (files) files->write_timeseries();
    return r;
  } catch (const StoppedByCallback& stopped) {
    view_ = ViewTime{};
    last_counters_ = observer.last();
    // As the engines end a run at stop.time: the observers hear of the time, the state
    // moves there (positions are lazy), and the run finishes.
    const RunResult r{StopReason::time, observer.last(), {}, 0.0};
    RunObserver<D>& recorders = files ? static_cast<RunObserver<D>&>(files->recorders()) : no_recorders;
    if (!std::isnan(stopped.time)) {
      recorders.before_event(state_, stopped.time);
      state_.time = stopped.time;
    }
    recorders.on_finish(state_, r);
    if (files) files->write_timeseries();
    throw;
  } catch (...) {
    view_ = ViewTime{};
    if (files) files->abandon();
    throw;
  }
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace ballagg::python
