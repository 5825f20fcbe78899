// Every function of src/ballagg/analysis/ on numpy arrays (docs/python.md, docs/analysis.md
// for the definitions): positions are (n, D) arrays, D = 2 or 3.
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "analysis_convert.hpp"
#include "bindings.hpp"

#include "ballagg/analysis/cluster_partition.hpp"
#include "ballagg/analysis/contacts.hpp"

namespace ballagg::python {

template <int D>
py::dict gyration_dict(const GyrationShape<D>& g) {
  py::dict d;
  d["centroid"] = from_vec<D>(g.centroid);
  d["eigenvalues"] = std::vector<double>(g.eigenvalues.begin(), g.eigenvalues.end());
  d["axes"] = from_points<D>(std::vector<Vec<D>>(g.axes.begin(), g.axes.end()));
  d["aspect_ratio"] = g.aspect_ratio;
  d["radius_of_gyration"] = g.radius_of_gyration;
  d["orientation"] = from_vec<D>(g.orientation());
  return d;
}

py::dict box_counting_dict(const BoxCounting& b) {
  py::dict d;
  d["level"] = from_vector(b.level);
  d["eps"] = from_vector(b.eps);
  d["boxes"] = from_vector(b.boxes);
  d["fitted"] = from_vector(std::vector<std::uint8_t>(b.fitted.begin(), b.fitted.end())).attr("astype")("bool");
  d["fit"] = fit_object(b.fit);
  d["dimension"] = b.dimension;
  d["dimension_error"] = b.dimension_error;
  d["prefactor"] = b.prefactor;
  d["prefactor_error"] = b.prefactor_error;
  d["flaw"] = flaw_code(b.flaw);
  return d;
}

py::dict pair_distribution_dict(const PairDistribution& p) {
  py::dict d;
  d["r"] = from_vector(p.r);
  d["all"] = from_vector(p.all);
  d["cluster"] = from_vector(p.cluster);
  d["all_fit"] = fit_object(p.all_fit);
  d["cluster_fit"] = fit_object(p.cluster_fit);
  d["all_dimension"] = p.all_dimension;
  d["cluster_dimension"] = p.cluster_dimension;
  d["all_flaw"] = flaw_code(p.all_flaw);
  d["cluster_flaw"] = flaw_code(p.cluster_flaw);
  return d;
}

template <int D>
py::dict mass_radius_dict(const MassRadius<D>& m) {
  py::dict d;
  d["centre_of_mass"] = from_vec<D>(m.centre_of_mass);
  d["mass"] = m.mass;
  d["r_max"] = m.r_max;
  d["density"] = m.density;
  d["radius"] = from_vector(m.radius);
  d["enclosed"] = from_vector(m.enclosed);
  d["fitted"] = from_vector(std::vector<std::uint8_t>(m.fitted.begin(), m.fitted.end())).attr("astype")("bool");
  d["fit"] = fit_object(m.fit);
  d["dimension"] = m.dimension;
  d["dimension_error"] = m.dimension_error;
  d["dimension_flaw"] = flaw_code(m.dimension_flaw);
  d["richardson_dimension"] = m.richardson_dimension;
  d["richardson_dimension_error"] = m.richardson_dimension_error;
  d["richardson_flaw"] = flaw_code(m.richardson_flaw);
  d["nearest_centre"] = m.nearest_centre;
  return d;
}

template <int D>
SphereTable<D> table_of(const Frame<D>& f, const Particles<D>& p) {
  SphereTable<D> t;
  for (int i = 0; i < f.size(); ++i) t.position.push_back(f.position[i]);
  t.velocity = f.velocity;
  t.radius = p.radius;
  t.mass = p.mass;
  t.cluster.assign(f.cluster.begin(), f.cluster.end());
  t.line.resize(f.size());
  t.source = "(python)";
  return t;
}

template <int D>
py::dict frame_dict(const Frame<D>& f, const Particles<D>& p) {
  py::dict d;
  d["time"] = f.time;
  d["step"] = f.step;
  d["positions"] = from_points<D>(f.position);
  d["velocities"] = from_points<D>(f.velocity);
  d["radii"] = from_vector(p.radius);
  d["masses"] = from_vector(p.mass);
  d["cluster_ids"] = from_vector(std::vector<std::int64_t>(f.cluster.begin(), f.cluster.end()));
  if (!f.image.empty()) {
    std::vector<Vec<D>> unwrapped(f.size());
    for (int i = 0; i < f.size(); ++i) unwrapped[i] = f.unwrapped(i, p.box.length);
    d["unwrapped_positions"] = from_points<D>(unwrapped);
  } else {
    d["unwrapped_positions"] = from_points<D>(f.position);
  }
  d["n_clusters"] = f.n_clusters;
  d["largest_cluster"] = f.largest_cluster;
  d["kinetic_energy"] = f.kinetic_energy;
  return d;
}

namespace {

std::vector<std::int32_t> labels_of(const IntArray& labels, std::size_t n) {
  const std::vector<std::int64_t> v = to_vector<std::int64_t>(labels, n, "cluster_ids");
  return {v.begin(), v.end()};
}

// Cluster labels renumbered 0, 1, ... in order of first sphere (what the functions expect).
std::vector<std::int32_t> partition_labels(const IntArray& labels, std::size_t n) {
  return partition_clusters(to_vector<std::int64_t>(labels, n, "cluster_ids"), static_cast<int>(n)).label;
}

}  // namespace

namespace {

// The functions of one cluster and of cluster labels: mass-radius, partitions, the mass
// spectrum, unwrapping, and the line fit they use.
void bind_cluster_functions(py::module_& m) {
  m.def("mass_radius", [](const IntArray& members, const DoubleArray& positions, const DoubleArray& radii,
                          const DoubleArray& masses, double length_unit, double radius_of_gyration) {
    return by_dimension(dimension_of(positions), [&]<int D>() -> py::object {
      const std::vector<Vec<D>> x = to_points<D>(positions);
      const std::vector<std::int64_t> m64(members.data(), members.data() + members.size());
      const std::vector<std::int32_t> ids(m64.begin(), m64.end());
      for (std::int32_t i : ids)
        if (i < 0 || static_cast<std::size_t>(i) >= x.size()) throw py::index_error("members: a sphere index out of range");
      return mass_radius_dict<D>(mass_radius<D>(ids, x, to_vector<double>(radii, x.size(), "radii"),
                                                to_vector<double>(masses, x.size(), "masses"), length_unit, radius_of_gyration));
    });
  }, py::arg("members"), py::arg("positions"), py::arg("radii"), py::arg("masses"), py::arg("length_unit"),
     py::arg("radius_of_gyration"), "Mass-radius relation of one cluster (unwrapped positions): R_max, f_D.");

  m.def("partition_clusters", [](const IntArray& cluster_ids) {
    const ClusterPartition p = partition_clusters(to_vector<std::int64_t>(cluster_ids, cluster_ids.size(), "cluster_ids"),
                                                  static_cast<int>(cluster_ids.size()));
    py::dict d;
    d["label"] = from_vector(p.label);
    d["start"] = from_vector(p.start);
    d["members"] = from_vector(p.members);
    return d;
  }, py::arg("cluster_ids"), "Clusters numbered 0, 1, ... in order of first sphere; members grouped by cluster.");

  m.def("kth_largest_cluster", [](const IntArray& cluster_ids, int k) {
    return kth_largest_cluster(partition_labels(cluster_ids, cluster_ids.size()), k);
  }, py::arg("cluster_ids"), py::arg("k") = 1, "Index of the k-th largest cluster (1: the largest).");

  m.def("mass_spectrum", [](const IntArray& cluster_ids, const py::object& masses) {
    const int n = static_cast<int>(cluster_ids.size());
    const ClusterPartition clusters =
        partition_clusters(to_vector<std::int64_t>(cluster_ids, cluster_ids.size(), "cluster_ids"), n);
    const std::vector<double> mass =
        masses.is_none() ? std::vector<double>(n, 1.0) : to_vector<double>(masses.cast<DoubleArray>(), n, "masses");
    std::vector<std::pair<std::int32_t, double>> size_and_mass;
    for (int c = 0; c < clusters.n_clusters(); ++c) {
      double cluster_mass = 0.0;
      for (std::int32_t i : clusters.members_of(c)) cluster_mass += mass[i];
      size_and_mass.push_back({clusters.size(c), cluster_mass});
    }
    std::vector<std::int64_t> size, count;
    std::vector<double> bin_mass;
    for (const MassSpectrumBin& b : mass_spectrum(size_and_mass))
      size.push_back(b.size), bin_mass.push_back(b.mass), count.push_back(b.clusters);
    py::dict d;
    d["size"] = from_vector(size);
    d["mass"] = from_vector(bin_mass);
    d["clusters"] = from_vector(count);
    return d;
  }, py::arg("cluster_ids"), py::arg("masses") = py::none(),
     "Number of clusters of each size and mass (masses default to 1 per sphere).");

  m.def("unwrap_clusters", [](const DoubleArray& positions, const DoubleArray& radii, const IntArray& cluster_ids,
                              double box_length, bool periodic) {
    return by_dimension(dimension_of(positions), [&]<int D>() -> py::object {
      const std::vector<Vec<D>> x = to_points<D>(positions);
      const ClusterPartition p = partition_clusters(to_vector<std::int64_t>(cluster_ids, x.size(), "cluster_ids"),
                                                    static_cast<int>(x.size()));
      const UnwrappedClusters<D> u = unwrap_clusters<D>(make_box<D>(box_length, periodic), x,
                                                        to_vector<double>(radii, x.size(), "radii"), p);
      return py::make_tuple(from_points<D>(u.position),
                            from_vector(std::vector<std::uint8_t>(u.percolating.begin(), u.percolating.end())).attr("astype")("bool"));
    });
  }, py::arg("positions"), py::arg("radii"), py::arg("cluster_ids"), py::arg("box_length"), py::arg("periodic") = true,
     "Positions with every cluster in one piece across periodic faces, and which clusters percolate.");

  m.def("fit_line", [](const std::vector<double>& x, const std::vector<double>& y) { return fit_object(fit_line(x, y)); },
        py::arg("x"), py::arg("y"), "Least-squares line y = slope x + intercept with standard errors (None if degenerate).");
}

}  // namespace

void bind_analysis(py::module_& m) {
  bind_cluster_functions(m);
  m.def("analyze", [](const DoubleArray& positions, const DoubleArray& radii, const IntArray& cluster_ids,
                      double box_length, bool periodic, const py::object& masses, const py::object& velocities,
                      bool tables) {
    return by_dimension(dimension_of(positions), [&]<int D>() {
      SphereTable<D> t;
      t.position = to_points<D>(positions);
      const std::size_t n = t.position.size();
      t.radius = to_vector<double>(radii, n, "radii");
      t.mass = masses.is_none() ? std::vector<double>(n, 1.0) : to_vector<double>(masses.cast<DoubleArray>(), n, "masses");
      t.velocity = velocities.is_none() ? std::vector<Vec<D>>(n, Vec<D>::Zero()) : to_points<D>(velocities.cast<DoubleArray>(), "velocities");
      t.cluster = to_vector<std::int64_t>(cluster_ids, n, "cluster_ids");
      t.line.resize(n);
      t.source = "(python)";
      return aggregate_analysis<D>(make_box<D>(box_length, periodic), t, py::none(), tables);
    });
  }, py::arg("positions"), py::arg("radii"), py::arg("cluster_ids"), py::arg("box_length"), py::arg("periodic") = false,
     py::arg("masses") = py::none(), py::arg("velocities") = py::none(), py::arg("tables") = false,
     "Every indicator of `ballagg analyze` (docs/analysis.md) for a set of spheres: the dict of analysis.json; "
     "tables=True: (that dict, the CSV tables as {name: {column: array}}).");

  m.def("gyration_shape", [](const DoubleArray& points) {
    return by_dimension(dimension_of(points, "points"), [&]<int D>() -> py::object { return gyration_dict<D>(gyration_shape<D>(to_points<D>(points, "points"))); });
  }, py::arg("points"), "Gyration tensor of points: aspect ratio A_r (4.3), orientation D (4.4), R_g.");

  m.def("box_counting", [](const DoubleArray& points, double box_length, bool periodic, std::optional<double> length_unit,
                           const py::object& radii) {
    return by_dimension(dimension_of(points, "points"), [&]<int D>() -> py::object {
      const std::vector<Vec<D>> x = to_points<D>(points, "points");
      const double unit = length_unit ? *length_unit
                          : radii.is_none() ? SystemConfig{}.radius
                                            : length_unit_of(to_vector<double>(radii.cast<DoubleArray>(), x.size(), "radii"));
      if (!(unit > 0.0) || !std::isfinite(unit)) throw py::value_error(fmt::format("length_unit = {}: must be a number > 0", unit));
      return box_counting_dict(box_counting<D>(make_box<D>(box_length, periodic), x, unit));
    });
  }, py::arg("points"), py::arg("box_length"), py::arg("periodic") = false, py::arg("length_unit") = py::none(),
     py::arg("radii") = py::none(),
     "Box-counting dimension (4.7) of points in the box, fitted over 3 length_unit <= eps <= L/2. length_unit is the "
     "sphere radius R, as in `ballagg analyze`: by default R of `radii` (their common value, else their mean), or "
     "without radii the default system.radius (0.2).");

  m.def("count_contacts", [](const DoubleArray& positions, const DoubleArray& radii, const IntArray& cluster_ids,
                             double box_length, bool periodic, double alpha_r) {
    return by_dimension(dimension_of(positions), [&]<int D>() -> py::object {
      const std::vector<Vec<D>> x = to_points<D>(positions);
      const ContactCounts c = count_contacts<D>(make_box<D>(box_length, periodic), x,
                                                to_vector<double>(radii, x.size(), "radii"), labels_of(cluster_ids, x.size()), alpha_r);
      py::dict d;
      d["all"] = from_vector(c.all);
      d["same_cluster"] = from_vector(c.same_cluster);
      std::int64_t sum = 0;
      for (std::int32_t k : c.all) sum += k;
      d["relative"] = relative_contacts<D>(sum, static_cast<std::int64_t>(x.size()));  // N_c (4.5)
      return d;
    });
  }, py::arg("positions"), py::arg("radii"), py::arg("cluster_ids"), py::arg("box_length"), py::arg("periodic") = false,
     py::arg("alpha_r") = kContactFactor, "Contacts per sphere within alpha_r R (4.5) and N_c.");

  m.def("relative_contacts", [](std::int64_t contact_sum, std::int64_t n_spheres, int dimension) {
    return dimension == 2 ? relative_contacts<2>(contact_sum, n_spheres) : relative_contacts<3>(contact_sum, n_spheres);
  }, py::arg("contact_sum"), py::arg("n_spheres"), py::arg("dimension"), "N_c of (4.5): contacts / (N N_max).");

  m.def("pair_distribution", [](const DoubleArray& positions, double mean_radius, const IntArray& cluster_ids,
                                int cluster, double box_length, bool periodic, double cluster_extent) {
    return by_dimension(dimension_of(positions), [&]<int D>() -> py::object {
      const std::vector<Vec<D>> x = to_points<D>(positions);
      return pair_distribution_dict(pair_distribution<D>(make_box<D>(box_length, periodic), x, mean_radius,
                                                         partition_labels(cluster_ids, x.size()), cluster,
                                                         cluster_extent));
    });
  }, py::arg("positions"), py::arg("mean_radius"), py::arg("cluster_ids"), py::arg("cluster"), py::arg("box_length"),
     py::arg("periodic") = false, py::arg("cluster_extent") = std::numeric_limits<double>::infinity(),
     "P(r) (4.6) of all spheres and of one cluster (its index in order of first sphere); the cluster's fit "
     "stops at cluster_extent (an upper bound on its diameter).");
}

template py::dict gyration_dict<2>(const GyrationShape<2>&);
template py::dict gyration_dict<3>(const GyrationShape<3>&);
template SphereTable<2> table_of<2>(const Frame<2>&, const Particles<2>&);
template SphereTable<3> table_of<3>(const Frame<3>&, const Particles<3>&);
template py::dict frame_dict<2>(const Frame<2>&, const Particles<2>&);
template py::dict frame_dict<3>(const Frame<3>&, const Particles<3>&);

}  // namespace ballagg::python
