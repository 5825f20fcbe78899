#include "ballagg/analysis/pair_distribution.hpp"

#include <cmath>
#include <limits>

#include "ballagg/spatial/pair_scan.hpp"

namespace ballagg {

template <int D>
PairDistribution pair_distribution(const Box<D>& box, const std::vector<Vec<D>>& x, double mean_radius,
                                   const std::vector<std::int32_t>& label, std::int32_t cluster,
                                   double cluster_extent) {
  PairDistribution p;
  const int steps = static_cast<int>(std::lround((kPairDistributionMax - kPairDistributionMin) / kPairDistributionStep));
  for (int k = 0; k <= steps; ++k) p.r.push_back((kPairDistributionMin + k * kPairDistributionStep) * mean_radius);
  const int bins = static_cast<int>(p.r.size());
  // bin b counts the pairs with r[b-1] < distance <= r[b] (bin 0: distance <= r[0]).
  auto bin_of = [&](double d) {
    int b = static_cast<int>(std::ceil((d - p.r[0]) / (kPairDistributionStep * mean_radius)));
    b = std::clamp(b, 0, bins - 1);
    while (b > 0 && d <= p.r[b - 1]) --b;  // exact comparisons at the table's distances
    while (b < bins - 1 && d > p.r[b]) ++b;
    return b;
  };
  const int threads = max_threads();
  std::vector<std::vector<std::int64_t>> all(threads, std::vector<std::int64_t>(bins, 0));
  std::vector<std::vector<std::int64_t>> own(threads, std::vector<std::int64_t>(bins, 0));
  // Each unordered pair once: it counts for both of its spheres in the sum over i != j.
  for_each_pair_within(box, x, p.r.back(), [&](int thread, int i, int j, double d) {
    const int b = bin_of(d);
    all[thread][b] += 2;
    if (label[i] == cluster && label[j] == cluster) own[thread][b] += 2;
  });
  std::int64_t cluster_size = 0;
  for (std::int32_t l : label) cluster_size += l == cluster;
  std::int64_t sum_all = 0, sum_own = 0;
  const double n = static_cast<double>(x.size());
  for (int b = 0; b < bins; ++b) {
    for (int t = 0; t < threads; ++t) sum_all += all[t][b], sum_own += own[t][b];
    p.all.push_back(n > 0 ? static_cast<double>(sum_all) / n : 0.0);
    p.cluster.push_back(cluster_size > 0 ? static_cast<double>(sum_own) / static_cast<double>(cluster_size) : 0.0);
  }
  // Only where P > 0 (a cluster too small to reach r has no pairs there), up to `last`.
  auto fit = [&](const std::vector<double>& values, double last) {
    std::vector<double> log_r, log_p;
    for (std::size_t k = 0; k < values.size() && p.r[k] <= last; ++k)
      if (values[k] > 0.0) log_r.push_back(std::log(p.r[k])), log_p.push_back(std::log(values[k]));
    return fit_line(log_r, log_p);
  };
  auto flaw_of = [](const std::optional<LinearFit>& f) {
    return f && f->points >= kMinFitPoints ? dimension_range_flaw<D>(f->slope) : FitFlaw::too_few_points;
  };
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  p.all_fit = fit(p.all, p.r.back());
  p.cluster_fit = fit(p.cluster, cluster_extent);
  p.all_flaw = flaw_of(p.all_fit);
  p.cluster_flaw = flaw_of(p.cluster_fit);
  p.all_dimension = p.all_flaw == FitFlaw::none ? p.all_fit->slope : kNaN;
  p.cluster_dimension = p.cluster_flaw == FitFlaw::none ? p.cluster_fit->slope : kNaN;
  return p;
}

template PairDistribution pair_distribution<2>(const Box<2>&, const std::vector<Vec<2>>&, double,
                                               const std::vector<std::int32_t>&, std::int32_t, double);
template PairDistribution pair_distribution<3>(const Box<3>&, const std::vector<Vec<3>>&, double,
                                               const std::vector<std::int32_t>&, std::int32_t, double);

}  // namespace ballagg
