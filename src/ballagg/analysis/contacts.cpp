#include "ballagg/analysis/contacts.hpp"

#include <algorithm>
#include <atomic>

#include "ballagg/spatial/pair_scan.hpp"

namespace ballagg {

template <int D>
ContactCounts count_contacts(const Box<D>& box, const std::vector<Vec<D>>& x, const std::vector<double>& radius,
                             const std::vector<std::int32_t>& label, double alpha_r) {
  const int n = static_cast<int>(x.size());
  ContactCounts counts;
  counts.all.assign(n, 0);
  counts.same_cluster.assign(n, 0);
  if (n == 0) return counts;
  const double max_radius = *std::max_element(radius.begin(), radius.end());
  // Integer increments from several threads: atomic, and the sums do not depend on order.
  for_each_pair_within(box, x, alpha_r * max_radius, [&](int, int i, int j, double r) {
    if (r > 0.5 * alpha_r * (radius[i] + radius[j])) return;
    for (int k : {i, j}) {
      std::atomic_ref<std::int32_t>(counts.all[k]).fetch_add(1, std::memory_order_relaxed);
      if (label[i] == label[j])
        std::atomic_ref<std::int32_t>(counts.same_cluster[k]).fetch_add(1, std::memory_order_relaxed);
    }
  });
  return counts;
}

template ContactCounts count_contacts<2>(const Box<2>&, const std::vector<Vec<2>>&, const std::vector<double>&,
                                         const std::vector<std::int32_t>&, double);
template ContactCounts count_contacts<3>(const Box<3>&, const std::vector<Vec<3>>&, const std::vector<double>&,
                                         const std::vector<std::int32_t>&, double);

}  // namespace ballagg
