#pragma once
// The clusters of a sphere table (core/sphere_table.hpp): one per distinct value of its
// cluster column, numbered in order of first appearance, each listing its spheres in table
// order. Without a cluster column every sphere is a cluster of its own, numbered as the
// sphere, and nothing but the labels is stored. With one, the member lists are compressed
// rows: one array of sphere ids grouped by cluster and one start per cluster (8 bytes per
// sphere in all, where a list per cluster would cost a heap block per cluster).
#include <cstdint>
#include <span>
#include <vector>

namespace ballagg {

class ClusterGroups {
 public:
  // `column` holds one cluster value per sphere, or nothing (n spheres, each on its own).
  ClusterGroups(const std::vector<std::int64_t>& column, int n);

  int size() const { return static_cast<int>(count_); }
  // The cluster of sphere i.
  std::int32_t label(int i) const { return label_[i]; }
  // The spheres of cluster c in table order (the first is the cluster's root).
  std::span<const std::int32_t> members(int c) const {
    if (member_.empty()) return {&label_[c], 1};  // label_[c] == c: the sphere itself
    return {member_.data() + start_[c], static_cast<std::size_t>(start_[c + 1] - start_[c])};
  }
  // Gives the labels away (one per sphere, as State's spheres.cluster keeps them); the
  // groups are empty afterwards.
  std::vector<std::int32_t> take_labels() &&;

 private:
  void label_in_order_of_appearance(const std::vector<std::int64_t>& column);
  void group_members();

  std::vector<std::int32_t> label_;   // per sphere
  std::vector<std::int32_t> start_;   // per cluster, plus the end: members of c at [start_[c], start_[c + 1])
  std::vector<std::int32_t> member_;  // sphere ids grouped by cluster; empty when every sphere is its own
  std::size_t count_ = 0;
};

}  // namespace ballagg
