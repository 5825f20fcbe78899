#pragma once
// The parts of the `ballagg` Python module, one file each (module.cpp puts them together).
#include <pybind11/pybind11.h>

#include "ballagg/config/config.hpp"

namespace ballagg::python {

namespace py = pybind11;

// A Config from None (the defaults), a dict of sections or a path, with a dict of overrides.
Config config_from(const py::object& source, const py::object& overrides);

void bind_config(py::module_& m);
void bind_state(py::module_& m);
void bind_simulation(py::module_& m);
void bind_analysis(py::module_& m);
void bind_run_directory(py::module_& m);

}  // namespace ballagg::python
