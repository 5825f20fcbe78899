// ballagg.Simulation: a configuration's initial state and engine, run from Python with a
// callback every k events (time steps for ts), the state read as numpy arrays; and
// ballagg.run / resume / verify, the command line's run, run --resume and verify.
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "analysis_convert.hpp"
#include "bindings.hpp"

#include "ballagg/analysis/overlap.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/state_csv.hpp"
#include "ballagg/run/simulation.hpp"
#include "ballagg/run/verify_run.hpp"

namespace ballagg::python {
namespace {

// The callback returned False: the run ends after the event it was called for.
struct StoppedByCallback {};

template <int D>
class Simulation;

template <int D>
class PythonObserver final : public RunObserver<D> {
 public:
  PythonObserver(py::object callback, std::int64_t every, py::object self)
      : callback_(std::move(callback)), every_(every), self_(std::move(self)) {}
  void after_event(const State<D>&, const EventRecord&, const EngineCounters& c) override {
    last_ = c;
    if (!callback_.is_none() && ++calls_ % every_ == 0) {
      const py::object r = callback_(self_);
      if (py::isinstance<py::bool_>(r) && !r.cast<bool>()) throw StoppedByCallback{};
    }
    // Ctrl-C (KeyboardInterrupt) after any event: a flag test, nanoseconds.
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }
  const EngineCounters& last() const { return last_; }
  // The rigid-body engine writes rotated sphere positions into the state only for readers
  // that ask (RunObserver::next_position_read): the callback may read them after the event
  // it is called for.
  double next_position_read() const override {
    const bool calls_next = !callback_.is_none() && (calls_ + 1) % every_ == 0;
    return calls_next ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  }

 private:
  py::object callback_;
  std::int64_t every_;
  py::object self_;
  std::int64_t calls_ = 0;
  EngineCounters last_;
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

template <int D>
class Simulation {
 public:
  explicit Simulation(const Config& given)
      : state_(make_initial_state<D>(given)), config_(resolve_defaults(given, state_)), engine_(make_engine<D>(config_)) {}

  py::dict run(const py::object& self, const py::object& callback, std::int64_t every,
               std::optional<std::int64_t> clusters, std::optional<double> time, std::optional<double> wall_seconds) {
    // The engine is in the middle of an event while the callback runs: a second run from
    // there would work on a state and a calendar that the first one still holds.
    if (running_)
      throw std::runtime_error("Simulation.run called while the simulation runs (from its callback): return False from "
                            "the callback to end the run, then call run() again");
    if (every < 1) throw py::value_error("every must be >= 1");
    StopCriteria stop = stop_criteria(config_);
    // The checks of the configuration's [stop] keys, with the same words.
    if (clusters) {
      check_stop_clusters(*clusters, "Simulation.run argument clusters");
      stop.clusters = *clusters;
    }
    if (time) {
      check_stop_duration(*time, "Simulation.run argument time");
      stop.time = *time;
    }
    if (wall_seconds) {
      check_stop_duration(*wall_seconds, "Simulation.run argument wall_seconds");
      stop.wall_seconds = *wall_seconds;
    }
    PythonObserver<D> observer(callback, every, self);
    struct Running {
      bool& flag;
      explicit Running(bool& f) : flag(f) { flag = true; }
      ~Running() { flag = false; }
    } running(running_);
    try {
      const RunResult r = engine_->run(state_, stop, observer);
      return result_dict(to_string(r.reason), r.counters, r.wall_seconds);
    } catch (const StoppedByCallback&) {
      return result_dict("callback", observer.last(), 0.0);
    }
  }

  Frame<D> frame() const { return capture_frame(state_, state_.time, 0); }
  const State<D>& state() const { return state_; }
  const Config& config() const { return config_; }
  std::string_view engine() const { return engine_->name(); }

 private:
  State<D> state_;
  Config config_;
  std::unique_ptr<Engine<D>> engine_;
  bool running_ = false;  // inside run(): the callback may read the state, not run it
};

template <int D>
void bind_simulation_in(py::module_& m, const char* name) {
  using S = Simulation<D>;
  py::class_<S>(m, name, "A simulation in D dimensions (made by ballagg.Simulation(config))")
      .def("run", [](py::object self, const py::object& callback, std::int64_t every, std::optional<std::int64_t> clusters,
                     std::optional<double> time, std::optional<double> wall_seconds) {
        return self.cast<S&>().run(self, callback, every, clusters, time, wall_seconds);
      }, py::arg("callback") = py::none(), py::arg("every") = 1, py::arg("clusters") = py::none(),
         py::arg("time") = py::none(), py::arg("wall_seconds") = py::none(),
         "Runs until the configuration's stop criteria (or the ones given) hold. callback(sim) is called after "
         "every `every` events (ts: time steps); returning False ends the run there. Calling run() again goes on "
         "from the current state. Returns a dict: stop_reason, events, collisions, merges, ...")
      .def_property_readonly("dimension", [](const S&) { return D; })
      .def_property_readonly("engine", [](const S& s) { return std::string(s.engine()); })
      .def_property_readonly("config", [](const S& s) { return s.config(); }, "The resolved configuration")
      .def_property_readonly("time", [](const S& s) { return s.state().time; })
      .def_property_readonly("n_spheres", [](const S& s) { return s.state().n_spheres(); })
      .def_property_readonly("n_clusters", [](const S& s) { return s.state().n_clusters(); })
      .def_property_readonly("largest_cluster", [](const S& s) { return s.state().largest_cluster(); })
      .def_property_readonly("kinetic_energy", [](const S& s) { return s.state().kinetic_energy(); })
      .def_property_readonly("momentum", [](const S& s) { return from_vec<D>(s.state().momentum()); })
      .def_property_readonly("wall_impulse", [](const S& s) { return from_vec<D>(s.state().wall_impulse()); })
      .def_property_readonly("box_length", [](const S& s) { return s.state().box.length; })
      .def_property_readonly("periodic", [](const S& s) { return s.state().box.periodic(); })
      .def_property_readonly("positions", [](const S& s) { return from_points<D>(s.frame().position); },
                             "(n, D) sphere centres now, folded into a periodic box")
      .def_property_readonly("unwrapped_positions", [](const S& s) {
        const Frame<D> f = s.frame();
        std::vector<Vec<D>> x(f.size());
        for (int i = 0; i < f.size(); ++i) x[i] = f.unwrapped(i, s.state().box.length);
        return from_points<D>(x);
      }, "(n, D) centres with every cluster in one piece across periodic faces")
      .def_property_readonly("velocities", [](const S& s) { return from_points<D>(s.frame().velocity); })
      .def_property_readonly("angular_velocities", [](const S& s) -> py::object {
        const State<D>& st = s.state();
        if (st.spin.empty()) return py::none();
        std::vector<Spin<D>> w(st.n_spheres());
        for (int i = 0; i < st.n_spheres(); ++i) w[i] = st.spin[st.spheres.cluster[i]].angular_velocity;
        return from_spins<D>(w);
      }, "Per sphere: its body's angular velocity, (n, 3) in 3D, (n,) in 2D (rigid-body engine; None otherwise)")
      .def_property_readonly("rotational_energy", [](const S& s) {
        double e = 0.0;
        if (!s.state().spin.empty())
          for (int c : s.state().alive_clusters()) e += s.state().spin[c].energy();
        return e;
      }, "Sum of 1/2 omega . h over the bodies (Richardson eq. 2; 0 unless the engine is rigid-body)")
      .def_property_readonly("radii", [](const S& s) { return from_vector(s.state().spheres.radius); })
      .def_property_readonly("masses", [](const S& s) { return from_vector(s.state().spheres.mass); })
      .def_property_readonly("cluster_ids", [](const S& s) {
        const Frame<D> f = s.frame();
        return from_vector(std::vector<std::int64_t>(f.cluster.begin(), f.cluster.end()));
      }, "Per sphere: its cluster, 0, 1, ... in order of each cluster's first sphere (as final.csv)")
      .def("max_overlap", [](const S& s) { return max_relative_overlap(s.state()); },
           "Largest (R_i + R_j - d) / (R_i + R_j) over close pairs (None if no pair is close)")
      .def("analyze", [](const S& s, bool tables) {
        const Frame<D> f = s.frame();
        return aggregate_analysis<D>(s.state().box, table_of<D>(f, particles_of(s.state())), py::none(), tables);
      }, py::arg("tables") = false,
         "Every indicator of `ballagg analyze` for the current state: the dict of analysis.json; tables=True: "
         "(that dict, the CSV tables as {name: {column: array}})")
      .def("write_state", [](const S& s, const std::string& path) {
        const std::filesystem::path p(path);
        write_file_atomically(p.parent_path().empty() ? "." : p.parent_path().string(), p.filename().string(),
                              state_csv_text(s.state()));
      }, py::arg("path"), "Writes the current state as a final.csv file (usable as initial.file)");
}

}  // namespace

void bind_simulation(py::module_& m) {
  bind_simulation_in<2>(m, "Simulation2D");
  bind_simulation_in<3>(m, "Simulation3D");
  m.def("Simulation", [](const py::object& config, const py::object& overrides) -> py::object {
    if (py::isinstance<Config>(config) && !overrides.is_none())
      throw py::value_error("overrides apply to a dict or a TOML path, not to a Config");
    const Config c = py::isinstance<Config>(config) ? config.cast<Config>() : config_from(config, overrides);
    if (c.system.dimension == 2) return py::cast(Simulation<2>(c));
    return py::cast(Simulation<3>(c));
  }, py::arg("config") = py::none(), py::arg("overrides") = py::none(),
     "A simulation of a Config (or of what Config() accepts: None, a dict, a TOML path), at its initial state.");

  m.def("run", [](const py::object& config, const std::string& out, bool quiet, bool overwrite) {
    const Config c = py::isinstance<Config>(config) ? config.cast<Config>() : config_from(config, py::none());
    RunOptions options{out, quiet, false, false};
    options.overwrite = overwrite;
    return run_simulation(c, options);
  }, py::arg("config") = py::none(), py::arg("out") = "", py::arg("quiet") = true, py::arg("overwrite") = false,
     "`ballagg run`: runs a configuration and writes its run directory (default out/<timestamp>); returns it. A "
     "directory holding another run is refused unless overwrite=True (`--overwrite`).");
  m.def("resume", [](const std::string& dir, bool quiet) { return resume_simulation(dir, {dir, quiet, false, false}); },
        py::arg("dir"), py::arg("quiet") = true, "`ballagg run --resume DIR`: finishes an interrupted run.");
  m.def("verify", [](const std::string& dir) {
    const Verification v = verify_run(dir);
    py::dict d;
    d["checks"] = v.checks;
    d["violations"] = v.violations;
    d["notes"] = v.notes;
    return d;
  }, py::arg("dir"), "`ballagg verify DIR`: a dict of checks made, violations (empty when all hold) and notes.");
}

}  // namespace ballagg::python
