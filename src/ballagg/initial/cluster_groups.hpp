#pragma once
// The clusters of a sphere table (core/sphere_table.hpp) as an initial state is assembled
// from them: the partition of analysis/cluster_partition.hpp (clusters numbered in order
// of first appearance, members in table order, as compressed rows), except that a table
// without a cluster column, where every sphere is a cluster of its own numbered as the
// sphere, stores nothing but the labels (4 bytes per sphere instead of 12).
#include <cstdint>
#include <span>
#include <vector>

#include "ballagg/analysis/cluster_partition.hpp"

namespace ballagg {

class ClusterGroups {
 public:
  // `column` holds one cluster value per sphere, or nothing (n spheres, each on its own).
  ClusterGroups(const std::vector<std::int64_t>& column, int n);

  int size() const { return count_; }
  // The cluster of sphere i.
  std::int32_t label(int i) const { return partition_.label[i]; }
  // The spheres of cluster c in table order (the first is the cluster's root).
  std::span<const std::int32_t> members(int c) const {
    if (partition_.members.empty()) return {&partition_.label[c], 1};  // label c is sphere c
    return partition_.members_of(c);
  }
  // Gives the labels away (one per sphere, as State's spheres.cluster keeps them); no
  // cluster is left afterwards.
  std::vector<std::int32_t> take_labels() &&;

 private:
  ClusterPartition partition_;
  int count_ = 0;
};

}  // namespace ballagg
