#pragma once
// Which spheres form each cluster, from per-sphere cluster labels: clusters numbered 0 ...
// M-1 in order of their first sphere (as in final.csv and trajectory frames), their
// members, their sizes, and their ranking by size. Shared by `ballagg analyze` and
// `ballagg render`.
#include <cstdint>
#include <span>
#include <vector>

namespace ballagg {

struct ClusterPartition {
  std::vector<std::int32_t> label;    // per sphere: its cluster, 0 ... M-1 in order of first sphere
  std::vector<std::int32_t> start;    // per cluster c: its members are members[start[c] .. start[c+1])
  std::vector<std::int32_t> members;  // sphere ids grouped by cluster, ascending in each

  int n_clusters() const { return static_cast<int>(start.size()) - 1; }
  int size(int c) const { return start[c + 1] - start[c]; }
  std::span<const std::int32_t> members_of(int c) const {
    return {members.data() + start[c], static_cast<std::size_t>(size(c))};
  }
};

// Clusters from per-sphere labels (any integers; equal labels = one cluster). Without
// labels (an empty vector) every one of the n spheres is its own cluster.
ClusterPartition partition_clusters(const std::vector<std::int64_t>& labels, int n);

// The label of the k-th largest cluster by number of spheres (k = 1: the largest; the
// lowest label on a tie), for labels 0 ... M-1. Returns -1 when there are fewer than k
// clusters.
int kth_largest_cluster(const std::vector<std::int32_t>& labels, int k);

}  // namespace ballagg
