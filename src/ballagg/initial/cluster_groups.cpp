#include "ballagg/initial/cluster_groups.hpp"

#include <numeric>
#include <utility>

namespace ballagg {

ClusterGroups::ClusterGroups(const std::vector<std::int64_t>& column, int n) {
  if (!column.empty()) {
    partition_ = partition_clusters(column, n);
    count_ = partition_.n_clusters();
    return;
  }
  partition_.label.resize(n);
  std::iota(partition_.label.begin(), partition_.label.end(), 0);
  count_ = n;
}

std::vector<std::int32_t> ClusterGroups::take_labels() && {
  count_ = 0;
  partition_.start = {};
  partition_.members = {};
  return std::move(partition_.label);
}

}  // namespace ballagg
