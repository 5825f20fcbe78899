#pragma once
// Analysis results as Python dicts and numpy arrays (shared by the analysis functions, the
// Simulation and the loaded run directories).
#include "ballagg/analysis/aggregate_analysis.hpp"
#include "ballagg/io/frame.hpp"
#include "convert.hpp"

namespace ballagg::python {

template <int D>
py::dict gyration_dict(const GyrationShape<D>& g);
py::dict box_counting_dict(const BoxCounting& b);
py::dict pair_distribution_dict(const PairDistribution& p);
template <int D>
py::dict mass_radius_dict(const MassRadius<D>& m);
// analyze_aggregates of the spheres (docs/analysis.md) as analysis.json of `ballagg
// analyze` has it (the same text, read by Python's json: NaN is None), `state_file` its
// "state_file" (None: the spheres come from Python). With `tables`, the tuple (that
// dict, the CSV tables of `ballagg analyze` as {"clusters": {column: array}, ...}).
template <int D>
py::object aggregate_analysis(const Box<D>& box, const SphereTable<D>& spheres, const py::object& state_file,
                              bool tables);

// A frame (positions folded, image, velocities, cluster labels 0, 1, ...) as a table.
template <int D>
SphereTable<D> table_of(const Frame<D>& f, const Particles<D>& p);
// A frame as a dict of numpy arrays.
template <int D>
py::dict frame_dict(const Frame<D>& f, const Particles<D>& p);

}  // namespace ballagg::python
