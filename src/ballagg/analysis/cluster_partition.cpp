#include "ballagg/analysis/cluster_partition.hpp"

#include <algorithm>
#include <numeric>
#include <unordered_map>

namespace ballagg {

ClusterPartition partition_clusters(const std::vector<std::int64_t>& labels, int n) {
  ClusterPartition p;
  p.label.resize(n);
  std::unordered_map<std::int64_t, std::int32_t> dense;
  std::int32_t next = 0;
  for (int i = 0; i < n; ++i) {
    if (labels.empty()) {
      p.label[i] = next++;
      continue;
    }
    const auto [it, fresh] = dense.emplace(labels[i], next);
    if (fresh) ++next;
    p.label[i] = it->second;
  }
  // Counting sort by label: members ascending within each cluster.
  p.start.assign(next + 1, 0);
  for (int i = 0; i < n; ++i) ++p.start[p.label[i] + 1];
  for (int c = 0; c < next; ++c) p.start[c + 1] += p.start[c];
  p.members.resize(n);
  std::vector<std::int32_t> fill(p.start.begin(), p.start.end() - 1);
  for (int i = 0; i < n; ++i) p.members[fill[p.label[i]]++] = i;
  return p;
}

int kth_largest_cluster(const std::vector<std::int32_t>& labels, int k) {
  if (labels.empty() || k < 1) return -1;
  const int n_labels = *std::max_element(labels.begin(), labels.end()) + 1;
  if (k > n_labels) return -1;
  std::vector<int> size(n_labels, 0);
  for (std::int32_t l : labels) ++size[l];
  std::vector<int> order(n_labels);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return size[a] > size[b]; });
  return order[k - 1];
}

}  // namespace ballagg
