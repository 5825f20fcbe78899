#include "ballagg/initial/cluster_groups.hpp"

#include <map>
#include <numeric>
#include <utility>

namespace ballagg {

ClusterGroups::ClusterGroups(const std::vector<std::int64_t>& column, int n) {
  if (column.empty()) {
    label_.resize(n);
    std::iota(label_.begin(), label_.end(), 0);
    count_ = label_.size();
    return;
  }
  label_in_order_of_appearance(column);
  group_members();
}

void ClusterGroups::label_in_order_of_appearance(const std::vector<std::int64_t>& column) {
  label_.resize(column.size());
  std::map<std::int64_t, std::int32_t> id;
  for (std::size_t i = 0; i < column.size(); ++i) {
    const auto [it, fresh] = id.emplace(column[i], static_cast<std::int32_t>(id.size()));
    label_[i] = it->second;
  }
  count_ = id.size();
}

// A counting sort of the sphere ids by label: stable, so each cluster lists its spheres in
// table order.
void ClusterGroups::group_members() {
  start_.assign(count_ + 1, 0);
  for (std::int32_t c : label_) ++start_[c + 1];
  std::partial_sum(start_.begin(), start_.end(), start_.begin());
  std::vector<std::int32_t> next(start_.begin(), start_.end() - 1);
  member_.resize(label_.size());
  for (std::size_t i = 0; i < label_.size(); ++i) member_[next[label_[i]]++] = static_cast<std::int32_t>(i);
}

std::vector<std::int32_t> ClusterGroups::take_labels() && {
  start_.clear();
  member_.clear();
  count_ = 0;
  return std::move(label_);
}

}  // namespace ballagg
