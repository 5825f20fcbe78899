// ballagg.load(path): a finished run directory, as `ballagg analyze` and `render` read it:
// its configuration, summary, time series, final state and trajectory frames.
#include <filesystem>

#include "analysis_convert.hpp"
#include "bindings.hpp"

#include "ballagg/config/text_file.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/io/csv_reader.hpp"
#include "ballagg/io/h5md_reader.hpp"
#include "ballagg/run/analyze_kinetics.hpp"
#include "ballagg/run/run_directory.hpp"

namespace ballagg::python {
namespace {

// A numeric CSV table (timeseries.csv, kinetics_collapse.csv) as columns of numpy arrays,
// read by the strict reader every CSV file goes through: a field that is not a number, or a
// row of another width, raises InputError naming the file, the line and the column, instead
// of entering the arrays as 0 or shifting the columns.
py::dict csv_columns(const std::string& text, const std::string& source) {
  CsvReader csv(text, source, "");
  std::vector<std::vector<double>> columns(csv.columns().size());
  for (CsvRow row; csv.next(row);)
    for (std::size_t k = 0; k < columns.size(); ++k) columns[k].push_back(csv.number(row, static_cast<int>(k)));
  py::dict d;
  for (std::size_t k = 0; k < columns.size(); ++k) d[py::str(csv.columns()[k])] = from_vector(columns[k]);
  return d;
}

struct LoadedRun {
  RunDirectory run;
  py::object summary, timeseries;
  py::dict final_state;
  std::function<py::object(bool)> analyze;
  std::function<int()> n_frames;
  std::function<py::dict(int)> frame;
};

template <int D>
void load_state(LoadedRun& r) {
  Frame<D> f;
  Particles<D> p;
  std::vector<Spin<D>> spins;
  read_final_state<D>(r.run, f, p, &spins);
  r.final_state = frame_dict<D>(f, p);
  if (!spins.empty()) r.final_state["angular_velocities"] = from_spins<D>(spins);  // rigid-body runs
  r.analyze = [f, p, file = r.run.path("final.csv")](bool tables) {
    return aggregate_analysis<D>(p.box, table_of<D>(f, p), py::str(file), tables);
  };
  const std::string h5md = r.run.path("trajectory.h5md");
  std::error_code ec;
  if (std::filesystem::exists(h5md, ec)) {
    auto reader = std::make_shared<H5mdReader<D>>(h5md);
    r.n_frames = [reader] { return reader->frames(); };
    r.frame = [reader](int k) {
      if (k < 0) k += reader->frames();
      if (k < 0 || k >= reader->frames()) throw py::index_error("no such trajectory frame");
      return frame_dict<D>(reader->frame(k), reader->particles());
    };
  } else {
    r.n_frames = [] { return 0; };
    r.frame = [](int) -> py::dict { throw py::index_error("the run has no trajectory.h5md (output.snapshot_every = 0)"); };
  }
}

// Run.kinetics: the kinetic exponents of the run's time series (and the collapse of its frames).
py::object kinetics_of(const LoadedRun& r, std::optional<std::pair<double, double>> window, bool tables) {
  std::map<std::string, std::string> files = kinetics_of_run(r.run, window);
  py::object fits = json_loads(files.at("kinetics.json"));
  if (!tables) return fits;
  py::dict t;
  if (auto it = files.find("kinetics_collapse.csv"); it != files.end()) t["kinetics_collapse"] = csv_columns(it->second, r.run.path("kinetics_collapse.csv"));
  return py::make_tuple(fits, t);
}

}  // namespace

void bind_run_directory(py::module_& m) {
  py::class_<LoadedRun>(m, "Run", "A finished run directory (ballagg.load)")
      .def_property_readonly("dir", [](const LoadedRun& r) { return r.run.dir; })
      .def_property_readonly("config", [](const LoadedRun& r) { return r.run.config; })
      .def_readonly("summary", &LoadedRun::summary, "summary.json as a dict")
      .def_readonly("timeseries", &LoadedRun::timeseries, "timeseries.csv: column name -> numpy array")
      .def_readonly("final", &LoadedRun::final_state,
                    "The final state: positions, unwrapped_positions, velocities, radii, masses, cluster_ids, ...")
      .def("analyze", [](const LoadedRun& r, bool tables) { return r.analyze(tables); }, py::arg("tables") = false,
           "What `ballagg analyze` writes for final.csv: analysis.json as a dict; tables=True: (that dict, the CSV "
           "tables as {name: {column: array}})")
      .def("kinetics", &kinetics_of, py::arg("window") = py::none(), py::arg("tables") = false,
           "What `ballagg analyze --kinetics [--window T0,T1]` writes: kinetics.json as a dict (the exponents z and "
           "theta with their errors and window); tables=True: (that dict, {'kinetics_collapse': {column: array}}), "
           "the collapse present once `ballagg analyze --frames` has run")
      .def_property_readonly("n_frames", [](const LoadedRun& r) { return r.n_frames(); }, "Frames in trajectory.h5md")
      .def("frame", [](const LoadedRun& r, int k) { return r.frame(k); }, py::arg("k"),
           "Trajectory frame k (negative: from the end) as a dict like `final`");

  m.def("load", [](const py::object& path) {
    LoadedRun r;
    r.run = open_run_directory(py::str(path).cast<std::string>());
    r.summary = json_loads(read_text_file(r.run.path("summary.json"), "run summary", kMaxSettingsFileBytes));
    std::error_code ec;
    const std::string timeseries = r.run.path("timeseries.csv");
    r.timeseries = std::filesystem::exists(timeseries, ec)
                       ? py::object(csv_columns(read_text_file(timeseries, "time series", kMaxStateFileBytes), timeseries))
                       : py::object(py::dict());
    if (r.run.config.system.dimension == 2) load_state<2>(r);
    else load_state<3>(r);
    return r;
  }, py::arg("path"), "Reads a run directory written by `ballagg run` (or ballagg.run).");
}

}  // namespace ballagg::python
