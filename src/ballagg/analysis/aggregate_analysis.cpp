#include "ballagg/analysis/aggregate_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "ballagg/analysis/contacts.hpp"

namespace ballagg {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <int D>
std::vector<Vec<D>> gather(std::span<const std::int32_t> members, const std::vector<Vec<D>>& x) {
  std::vector<Vec<D>> out;
  out.reserve(members.size());
  for (int i : members) out.push_back(x[i]);
  return out;
}

template <int D>
PopulationFits population_fits(const std::vector<ClusterSummary<D>>& clusters) {
  PopulationFits p;
  p.dimension = kNaN;
  std::vector<double> log_n, log_r, log_rho;
  std::vector<int> sizes;
  for (const ClusterSummary<D>& c : clusters) {
    if (c.size < kPopulationMinSize) continue;
    log_n.push_back(std::log(static_cast<double>(c.size)));
    log_r.push_back(std::log(c.r_max));
    log_rho.push_back(std::log(c.density));
    sizes.push_back(c.size);
  }
  p.clusters = static_cast<int>(sizes.size());
  std::sort(sizes.begin(), sizes.end());
  p.dimension_flaw = FitFlaw::too_few_points;
  if (std::unique(sizes.begin(), sizes.end()) - sizes.begin() < kPopulationMinSizes) return p;
  p.r_max = fit_line(log_n, log_r);
  p.density = fit_line(log_n, log_rho);
  if (!p.density) return p;
  // gamma >= 1 (a density that does not fall with size) implies no dimension at all.
  const double implied = D / (1.0 - p.density->slope);
  p.dimension_flaw = dimension_range_flaw<D>(implied);
  if (p.dimension_flaw == FitFlaw::none) p.dimension = implied;
  return p;
}

// Richardson's mean f_D with inverse-square weights, and the weighted spread about it.
template <int D>
WeightedMean weighted_mean(const std::vector<ClusterSummary<D>>& clusters, double ClusterSummary<D>::*value,
                           double ClusterSummary<D>::*error) {
  double weight = 0.0, weighted = 0.0, weighted_square = 0.0;
  WeightedMean m;
  for (const ClusterSummary<D>& c : clusters) {
    const double f = c.*value, e = c.*error;
    if (!std::isfinite(f) || !std::isfinite(e) || !(e > 0.0)) continue;
    const double w = 1.0 / (e * e);
    weight += w;
    weighted += w * f;
    weighted_square += w * f * f;
    ++m.clusters;
  }
  m.mean = m.spread = kNaN;
  if (m.clusters == 0) return m;
  m.mean = weighted / weight;
  m.spread = std::sqrt(std::max(0.0, weighted_square / weight - m.mean * m.mean));
  return m;
}

// The largest side of the box that bounds a cluster's spheres (in one piece), or the box for
// a cluster that wraps around the periodic box, whose unwrapped extent measures nothing.
template <int D>
double extent_of(std::span<const std::int32_t> members, const UnwrappedClusters<D>& unwrapped,
                 const std::vector<double>& radius, bool percolating, const Box<D>& box) {
  if (percolating) return box.length;
  Vec<D> low = Vec<D>::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (int i : members) {
    low = low.cwiseMin(unwrapped.position[i] - Vec<D>::Constant(radius[i]));
    high = high.cwiseMax(unwrapped.position[i] + Vec<D>::Constant(radius[i]));
  }
  return (high - low).maxCoeff();
}

// Box counting of one cluster, fitted up to the level nearest half its extent (box_counting.hpp).
template <int D>
BoxCounting cluster_box_counting(const Box<D>& box, const std::vector<Vec<D>>& points, double length_unit,
                                 double extent) {
  return box_counting(box, points, length_unit, kBoxCountingCoarsestOfExtent * extent);
}

// Mass fractions and total kinetic energies over the clusters.
template <int D>
void mass_and_energy_totals(AggregateAnalysis<D>& a) {
  double aggregated = 0.0, heaviest = 0.0;
  std::vector<std::pair<std::int32_t, double>> size_and_mass;
  size_and_mass.reserve(a.clusters.size());
  for (const ClusterSummary<D>& c : a.clusters) {
    a.mass += c.mass;
    if (c.size > 1) aggregated += c.mass;
    heaviest = std::max(heaviest, c.mass);
    a.translational_energy += c.motion.translational_energy;
    a.rotational_energy += c.motion.rotational_energy;
    size_and_mass.emplace_back(c.size, c.mass);
  }
  a.aggregated_mass_fraction = aggregated / a.mass;
  a.heaviest_mass_fraction = heaviest / a.mass;
  a.mass_spectrum = mass_spectrum(std::move(size_and_mass));
}

}  // namespace

double length_unit_of(const std::vector<double>& radii) {
  const auto [smallest, largest] = std::minmax_element(radii.begin(), radii.end());
  if (smallest == radii.end()) return std::numeric_limits<double>::quiet_NaN();
  return *smallest == *largest ? *smallest
                               : std::accumulate(radii.begin(), radii.end(), 0.0) / static_cast<double>(radii.size());
}

template <int D>
AggregateAnalysis<D> analyze_aggregates(const Box<D>& box, const SphereTable<D>& t) {
  AggregateAnalysis<D> a;
  a.box = box;
  a.n_spheres = static_cast<int>(t.radius.size());
  a.length_unit = length_unit_of(t.radius);
  const ClusterPartition partition = partition_clusters(t.cluster, a.n_spheres);
  const UnwrappedClusters<D> unwrapped = unwrap_clusters(box, t.position, t.radius, partition);

  const ContactCounts contacts = count_contacts(box, t.position, t.radius, partition.label);
  const std::int64_t all_contacts = std::accumulate(contacts.all.begin(), contacts.all.end(), std::int64_t{0});
  a.contacts = relative_contacts<D>(all_contacts, a.n_spheres);
  a.box_counting = box_counting(box, t.position, a.length_unit);

  a.largest = kth_largest_cluster(partition.label, 1);
  const int m = partition.n_clusters();
  a.clusters.resize(m);
  for (int c = 0; c < m; ++c) {
    const std::span<const std::int32_t> members = partition.members_of(c);
    ClusterSummary<D>& s = a.clusters[c];
    s.size = partition.size(c);
    s.percolating = unwrapped.percolating[c];
    s.shape = gyration_shape(gather(members, unwrapped.position));
    const MassRadius<D> mr =
        mass_radius<D>(members, unwrapped.position, t.radius, t.mass, a.length_unit, s.shape.radius_of_gyration);
    s.mass = mr.mass;
    s.centre_of_mass = mr.centre_of_mass;
    s.r_max = mr.r_max;
    s.density = mr.density;
    s.motion = cluster_motion<D>(members, unwrapped.position, t);
    s.richardson_dimension = mr.richardson_dimension;
    s.richardson_dimension_error = mr.richardson_dimension_error;
    std::int64_t own = 0;
    for (int i : members) own += contacts.same_cluster[i];
    s.contacts = relative_contacts<D>(own, s.size);
    s.richardson_dimension_flaw = mr.richardson_flaw;
    s.box_dimension = s.box_dimension_error = s.mass_radius_dimension = s.mass_radius_dimension_error = kNaN;
    s.box_dimension_flaw = s.mass_radius_dimension_flaw = FitFlaw::cluster_too_small;
    if (s.size >= kFractalMinSize) {
      const BoxCounting bc = cluster_box_counting(box, gather(members, t.position), a.length_unit,
                                                  extent_of(members, unwrapped, t.radius, s.percolating, box));
      s.box_dimension = bc.dimension;
      s.box_dimension_error = bc.dimension_error;
      s.box_dimension_flaw = bc.flaw;
      s.mass_radius_dimension = mr.dimension;
      s.mass_radius_dimension_error = mr.dimension_error;
      s.mass_radius_dimension_flaw = mr.dimension_flaw;
    }
  }
  const std::span<const std::int32_t> largest = partition.members_of(a.largest);
  const ClusterSummary<D>& biggest = a.clusters[a.largest];
  a.largest_box_counting = cluster_box_counting(box, gather(largest, t.position), a.length_unit,
                                                extent_of(largest, unwrapped, t.radius, biggest.percolating, box));
  a.largest_mass_radius = mass_radius<D>(largest, unwrapped.position, t.radius, t.mass, a.length_unit,
                                         a.clusters[a.largest].shape.radius_of_gyration);
  // P(r) of the cluster is flat beyond its largest pair distance, at most 2 R_max.
  a.pair_distribution = pair_distribution(box, t.position, a.length_unit, partition.label, a.largest,
                                          biggest.percolating ? box.length : 2.0 * biggest.r_max);
  a.population = population_fits(a.clusters);
  a.population.mass_radius_dimension = weighted_mean(a.clusters, &ClusterSummary<D>::mass_radius_dimension,
                                                     &ClusterSummary<D>::mass_radius_dimension_error);
  a.population.richardson_dimension = weighted_mean(a.clusters, &ClusterSummary<D>::richardson_dimension,
                                                    &ClusterSummary<D>::richardson_dimension_error);
  mass_and_energy_totals(a);
  return a;
}

template AggregateAnalysis<2> analyze_aggregates<2>(const Box<2>&, const SphereTable<2>&);
template AggregateAnalysis<3> analyze_aggregates<3>(const Box<3>&, const SphereTable<3>&);

}  // namespace ballagg
