#include "ballagg/io/frame_analysis_tables.hpp"

#include <iterator>
#include <limits>

namespace ballagg {
namespace {

// Shortest text that reads back as the same double ("nan", "inf" for withheld values, as
// in clusters.csv).
std::string num(double v) { return fmt::format("{}", v); }

template <class... Parts>
void put(fmt::memory_buffer& out, const Parts&... parts) {
  (fmt::format_to(std::back_inserter(out), "{}", parts), ...);
}

// The weight-average cluster mass, sum M^2 / sum M: the mean mass of the cluster a
// sphere belongs to, which the kinetic scaling laws follow.
template <int D>
double weight_average_mass(const AggregateAnalysis<D>& a) {
  double first = 0.0, second = 0.0;
  for (const ClusterSummary<D>& c : a.clusters) {
    first += c.mass;
    second += c.mass * c.mass;
  }
  return first > 0.0 ? second / first : 0.0;
}

}  // namespace

FrameAnalysisTables::FrameAnalysisTables() {
  put(frames_csv_,
      "time,step,n_spheres,n_clusters,mean_cluster_mass,weight_average_mass,largest_size,heaviest_mass_fraction,"
      "aggregated_mass_fraction,contacts,box_counting_dimension,box_counting_dimension_error,"
      "box_counting_dimension_flaw,correlation_dimension,largest_box_counting_dimension,"
      "largest_box_counting_dimension_error,largest_box_counting_dimension_flaw,largest_mass_radius_dimension,"
      "largest_mass_radius_dimension_error,largest_mass_radius_dimension_flaw,largest_radius_of_gyration,"
      "largest_r_max,largest_aspect_ratio,largest_contacts,r_max_exponent,r_max_exponent_error,"
      "dimension_from_density,dimension_from_density_flaw,mean_richardson_dimension,translational_energy,"
      "rotational_energy\n");
  put(spectrum_csv_, "time,size,mass,clusters\n");
  put(clusters_csv_, "time,cluster,size,mass,radius_of_gyration,r_max\n");
}

template <int D>
void FrameAnalysisTables::add(double time, std::int64_t step, const AggregateAnalysis<D>& a) {
  const ClusterSummary<D>& largest = a.clusters[a.largest];
  const auto& fit = a.population.r_max;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  put(frames_csv_, num(time), ",", step, ",", a.n_spheres, ",", a.clusters.size(), ",",
      num(a.mass / static_cast<double>(a.clusters.size())), ",", num(weight_average_mass(a)), ",", largest.size, ",",
      num(a.heaviest_mass_fraction), ",", num(a.aggregated_mass_fraction), ",", num(a.contacts), ",",
      num(a.box_counting.dimension), ",", num(a.box_counting.dimension_error), ",", flaw_code(a.box_counting.flaw),
      ",", num(a.pair_distribution.all_dimension), ",", num(a.largest_box_counting.dimension), ",",
      num(a.largest_box_counting.dimension_error), ",", flaw_code(a.largest_box_counting.flaw), ",",
      num(largest.mass_radius_dimension), ",", num(largest.mass_radius_dimension_error), ",",
      flaw_code(largest.mass_radius_dimension_flaw), ",", num(largest.shape.radius_of_gyration), ",",
      num(largest.r_max), ",", num(largest.shape.aspect_ratio), ",", num(largest.contacts), ",",
      num(fit ? fit->slope : nan), ",", num(fit ? fit->slope_error : nan), ",", num(a.population.dimension), ",",
      flaw_code(a.population.dimension_flaw), ",", num(a.population.richardson_dimension.mean), ",",
      num(a.translational_energy), ",", num(a.rotational_energy), "\n");
  for (const MassSpectrumBin& b : a.mass_spectrum) put(spectrum_csv_, num(time), ",", b.size, ",", num(b.mass), ",", b.clusters, "\n");
  for (std::size_t k = 0; k < a.clusters.size(); ++k) {
    const ClusterSummary<D>& c = a.clusters[k];
    if (c.size < kPopulationMinSize) continue;
    put(clusters_csv_, num(time), ",", k, ",", c.size, ",", num(c.mass), ",", num(c.shape.radius_of_gyration), ",",
        num(c.r_max), "\n");
  }
  ++frames_;
}

std::map<std::string, std::string> FrameAnalysisTables::files() const {
  return {{"frames.csv", fmt::to_string(frames_csv_)},
          {"frames_mass_spectrum.csv", fmt::to_string(spectrum_csv_)},
          {"frames_clusters.csv", fmt::to_string(clusters_csv_)}};
}

template void FrameAnalysisTables::add<2>(double, std::int64_t, const AggregateAnalysis<2>&);
template void FrameAnalysisTables::add<3>(double, std::int64_t, const AggregateAnalysis<3>&);

}  // namespace ballagg
