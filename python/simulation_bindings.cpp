// ballagg.Simulation bound to Python: run with a callback (every k events, or every dt of
// simulated time) and output files, the state read as numpy arrays; and ballagg.run /
// resume / verify, the command line's run, run --resume and verify.
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "analysis_convert.hpp"
#include "bindings.hpp"
#include "simulation.hpp"
#include "state_from_arrays.hpp"

#include "ballagg/analysis/overlap.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/state_csv.hpp"
#include "ballagg/run/simulation.hpp"
#include "ballagg/run/verify_run.hpp"

namespace ballagg::python {
namespace {

template <int D>
py::dict run_simulation_from_python(py::object self, const py::object& callback, std::optional<std::int64_t> every,
                                    std::optional<std::int64_t> clusters, std::optional<double> time,
                                    std::optional<double> wall_seconds, std::optional<double> every_time,
                                    const py::object& out, bool overwrite) {
  Simulation<D>& sim = self.cast<Simulation<D>&>();
  if (sim.running())  // before anything is checked or opened
    return sim.run(self, callback, {}, stop_criteria(sim.config()), {});
  CallbackSchedule when;
  if (every && every_time) throw py::value_error("give every (events) or every_time (simulated time), not both");
  if (every && *every < 1) throw py::value_error(fmt::format("every = {}: must be an integer >= 1", *every));
  if (every) when.events = *every;
  if (every_time) {
    check_stop_duration(*every_time, "Simulation.run argument every_time");
    if (std::isinf(*every_time)) throw InputError("Simulation.run argument every_time = inf: must be finite");
    when.every_time = *every_time;
  }
  const StopCriteria stop = stop_criteria_with(sim.config(), clusters, time, wall_seconds);
  RunOutputRequest output;
  if (!out.is_none()) output.out = py::str(out).cast<std::string>();
  output.overwrite = overwrite;
  return sim.run(self, callback, when, stop, output);
}

template <int D>
void bind_simulation_in(py::module_& m, const char* name) {
  using S = Simulation<D>;
  py::class_<S>(m, name, "A simulation in D dimensions (made by ballagg.Simulation(config))")
      .def("run", &run_simulation_from_python<D>, py::arg("callback") = py::none(), py::arg("every") = py::none(),
           py::arg("clusters") = py::none(), py::arg("time") = py::none(), py::arg("wall_seconds") = py::none(),
           py::kw_only(), py::arg("every_time") = py::none(), py::arg("out") = py::none(),
           py::arg("overwrite") = false,
           "Runs until the configuration's stop criteria (or the ones given) hold. callback(sim) is called after "
           "every `every` events (ts: time steps; default 1), or, with every_time=dt, at every t = k dt of simulated "
           "time in (start, end] with the state at exactly that time; returning False ends the run there. out=DIR "
           "writes the run's trajectory files and timeseries.csv into DIR as `ballagg run` does (overwrite=True "
           "replaces another run's files). Calling run() again goes on from the current state. Returns a dict: "
           "stop_reason, events, collisions, merges, ...")
      .def_property_readonly("dimension", [](const S&) { return D; })
      .def_property_readonly("engine", [](const S& s) { return std::string(s.engine()); })
      .def_property_readonly("config", [](const S& s) { return s.config(); }, "The resolved configuration")
      .def_property_readonly("time", [](const S& s) { return s.time(); },
                             "The simulated time (inside a call of every_time: the multiple of it called for)")
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
      .def("max_overlap", [](const S& s) { return max_relative_overlap(s.state_now()); },
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
                              state_csv_text(s.state_now()));
      }, py::arg("path"), "Writes the current state as a final.csv file (usable as initial.file)");
}

}  // namespace

void bind_simulation(py::module_& m) {
  bind_simulation_in<2>(m, "Simulation2D");
  bind_simulation_in<3>(m, "Simulation3D");
  m.def("Simulation", [](const py::object& config, const py::object& overrides, const py::object& state) -> py::object {
    if (py::isinstance<Config>(config) && !overrides.is_none())
      throw py::value_error("overrides apply to a dict or a TOML path, not to a Config");
    const Config c = py::isinstance<Config>(config) ? config.cast<Config>() : config_from(config, overrides);
    if (!state.is_none()) {
      const ArrayState& s = state.cast<const ArrayState&>();
      return by_dimension(s.dimension, [&]<int D>() -> py::object {
        const Config given = config_for_state<D>(c, s);
        return py::cast(Simulation<D>(given, state_from_spheres<D>(given, std::get<SphereTable<D>>(s.spheres))));
      });
    }
    if (c.system.dimension == 2) return py::cast(Simulation<2>(c));
    return py::cast(Simulation<3>(c));
  }, py::arg("config") = py::none(), py::arg("overrides") = py::none(), py::kw_only(), py::arg("state") = py::none(),
     "A simulation of a Config (or of what Config() accepts: None, a dict, a TOML path), at its initial state, or at "
     "`state` (a ballagg.State: its spheres and box length, checked as a state file is).");

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
