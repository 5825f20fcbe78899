// The `ballagg` Python module (docs/python.md): configurations, simulations with a
// callback, the state as numpy arrays, every analysis function, and run directories.
#include "bindings.hpp"

#include "ballagg/core/version.hpp"
#include "ballagg/io/output_error.hpp"

PYBIND11_MODULE(ballagg, m) {
  namespace py = pybind11;
  m.doc() = "ballagg: ballistic aggregation of hard spheres (2D and 3D), docs/python.md";
  m.attr("__version__") = ballagg::kVersion;
  // Bad input (a configuration value, a run directory): the message the command line prints.
  py::register_exception<ballagg::InputError>(m, "InputError", PyExc_ValueError);
  // An output file that cannot be written (a full disk, a device or link at its path).
  py::register_exception<ballagg::OutputError>(m, "OutputError", PyExc_OSError);
  ballagg::python::bind_config(m);
  ballagg::python::bind_state(m);
  ballagg::python::bind_simulation(m);
  ballagg::python::bind_analysis(m);
  ballagg::python::bind_run_directory(m);
}
