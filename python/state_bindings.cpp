// ballagg.State: spheres given as numpy arrays (positions, velocities, radii, masses,
// cluster ids, spins) and a box length, the start of a Simulation without a state file.
// The arrays' shapes and numbers are checked here; the rest (ranges, overlaps, glued
// clusters) as for a state file, when a Simulation is made of it (initial/initial_state.hpp).
#include <cmath>
#include <variant>

#include <fmt/format.h>

#include "bindings.hpp"
#include "convert.hpp"
#include "state_from_arrays.hpp"

namespace ballagg::python {
namespace {

// A 1-d array of n numbers, each finite: "radii[3] = nan: must be a finite number".
std::vector<double> finite_column(const DoubleArray& a, std::size_t n, const char* name) {
  std::vector<double> v = to_vector<double>(a, n, name);
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) throw InputError(fmt::format("{}[{}] = {}: must be a finite number", name, i, v[i]));
  return v;
}

// An (n, D) array of finite numbers: "positions[3, 1] = inf: must be a finite number".
template <int D>
std::vector<Vec<D>> finite_points(const DoubleArray& a, std::size_t n, const char* name) {
  if (a.ndim() != 2 || static_cast<std::size_t>(a.shape(0)) != n || a.shape(1) != D)
    throw py::value_error(fmt::format("{} must be an ({}, {}) array, as positions", name, n, D));
  std::vector<Vec<D>> v = to_points<D>(a, name);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < D; ++k)
      if (!std::isfinite(v[i][k]))
        throw InputError(fmt::format("{}[{}, {}] = {}: must be a finite number", name, i, k, v[i][k]));
  return v;
}

// Angular velocities, one per sphere: (n, 3) in 3D, (n,) in 2D (as Simulation gives them).
template <int D>
std::vector<Spin<D>> spins_of(const py::object& given, std::size_t n) {
  std::vector<Spin<D>> w(n);
  if constexpr (D == 3) {
    const std::vector<Vec<3>> v = finite_points<3>(given.cast<DoubleArray>(), n, "angular_velocities");
    std::copy(v.begin(), v.end(), w.begin());
  } else {
    const std::vector<double> v = finite_column(given.cast<DoubleArray>(), n, "angular_velocities");
    for (std::size_t i = 0; i < n; ++i) w[i][0] = v[i];
  }
  return w;
}

template <int D>
SphereTable<D> table_from_arrays(const DoubleArray& positions, const DoubleArray& velocities, const DoubleArray& radii,
                                 const DoubleArray& masses, const py::object& cluster_ids,
                                 const py::object& angular_velocities) {
  SphereTable<D> t;
  const std::size_t n = static_cast<std::size_t>(positions.shape(0));
  if (n == 0) throw py::value_error("positions: a state needs at least one sphere");
  t.position = finite_points<D>(positions, n, "positions");
  t.velocity = finite_points<D>(velocities, n, "velocities");
  t.radius = finite_column(radii, n, "radii");
  t.mass = finite_column(masses, n, "masses");
  if (!cluster_ids.is_none()) {
    const py::array ids = py::array::ensure(cluster_ids);
    if (!ids || (ids.dtype().kind() != 'i' && ids.dtype().kind() != 'u'))
      throw py::type_error("cluster_ids must be an array of integers (numpy int64, int32, ...)");
    t.cluster = to_vector<std::int64_t>(cluster_ids.cast<IntArray>(), n, "cluster_ids");
  }
  if (!angular_velocities.is_none()) t.spin = spins_of<D>(angular_velocities, n);
  t.source = "arrays";  // no file lines: errors name the arrays and the index
  return t;
}

}  // namespace

void bind_state(py::module_& m) {
  py::class_<ArrayState>(m, "State", "Spheres from numpy arrays, to start a Simulation from (Simulation(config, state=...))")
      .def_static("from_arrays", [](const DoubleArray& positions, const DoubleArray& velocities, const DoubleArray& radii,
                                    const DoubleArray& masses, const py::object& cluster_ids, double box_length,
                                    const py::object& angular_velocities) {
        if (!(box_length > 0.0) || !std::isfinite(box_length))
          throw InputError(fmt::format("box_length = {}: must be a number > 0", box_length));
        ArrayState s;
        s.box_length = box_length;
        s.dimension = dimension_of(positions);
        if (s.dimension == 2) s.spheres = table_from_arrays<2>(positions, velocities, radii, masses, cluster_ids, angular_velocities);
        else s.spheres = table_from_arrays<3>(positions, velocities, radii, masses, cluster_ids, angular_velocities);
        return s;
      }, py::arg("positions"), py::arg("velocities"), py::arg("radii"), py::arg("masses"),
         py::arg("cluster_ids") = py::none(), py::kw_only(), py::arg("box_length"),
         py::arg("angular_velocities") = py::none(),
         "positions, velocities (n, D), radii, masses (n,), cluster_ids (n,) integers (equal ids: one rigid cluster; "
         "default: every sphere its own), angular_velocities (rigid-body engine: (n, 3) in 3D, (n,) in 2D), and the "
         "box length. Checked as a state file is when a Simulation starts from it.")
      .def_property_readonly("dimension", [](const ArrayState& s) { return s.dimension; })
      .def_property_readonly("box_length", [](const ArrayState& s) { return s.box_length; })
      .def_property_readonly("n_spheres", [](const ArrayState& s) {
        return std::visit([](const auto& t) { return t.radius.size(); }, s.spheres);
      });
}

template <int D>
Config config_for_state(Config c, const ArrayState& s) {
  if (c.system.dimension != s.dimension)
    throw InputError(fmt::format("the state is {}D (positions of {} columns), the configuration {}D (system.dimension)",
                                 s.dimension, s.dimension, c.system.dimension));
  // The state gives the box and the spheres; the configuration's [initial] keys are not read.
  c.system.box_length = s.box_length;
  c.system.volume_fraction.reset();
  c.initial.lattice_spacing.reset();  // it sets the box too, which the state gives
  c.system.n = static_cast<std::int64_t>(std::get<SphereTable<D>>(s.spheres).radius.size());
  return c;
}

template Config config_for_state<2>(Config, const ArrayState&);
template Config config_for_state<3>(Config, const ArrayState&);

}  // namespace ballagg::python
