#pragma once
// Which body of a group each sphere belongs to, in O(1) per sphere.
//
// The searches around a group (its guards, its retreat) ask for every sphere they meet
// whether it is in the group and in which of its bodies: body_index (minimisation_problem.hpp)
// looks up the body of the sphere's cluster and searches the group's bodies for it, and
// the retreats of a large run ask it tens of millions of times. Here the group's clusters
// are marked with their body index in an array over cluster ids that the calling thread
// keeps from one group to the next; a stamp per group tells the marks of earlier groups
// apart, so a group costs O(its clusters), not O(cluster ids). The array takes 8 bytes per
// cluster id per thread that uses it, kept until the thread ends.
//
// Other threads may read the marks while their maker waits for them (the retreat shares
// its searches among threads); a thread holds one GroupMarks at a time.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

namespace ballagg {

class GroupMarks {
 public:
  // cluster_of_sphere: each sphere's cluster id, below n_cluster_ids; clusters: the
  // group's clusters, each with the index of its body in the group.
  GroupMarks(const std::vector<std::int32_t>& cluster_of_sphere, std::size_t n_cluster_ids,
             const std::vector<std::pair<std::int32_t, std::int32_t>>& clusters)
      : cluster_of_sphere_(cluster_of_sphere.data()), marks_(thread_marks()) {
    if (held()) throw std::logic_error("GroupMarks: a thread holds two at once");
    held() = true;
    if (marks_.size() < n_cluster_ids) marks_.resize(n_cluster_ids, 0);
    if (++thread_stamp() == kStampsPerClear) {  // after 2^32 - 1 groups: old marks could match again
      std::fill(marks_.begin(), marks_.end(), 0);
      thread_stamp() = 1;
    }
    stamp_ = thread_stamp() << 32;
    for (const auto& [c, b] : clusters) marks_[c] = stamp_ | static_cast<std::uint32_t>(b);
  }
  GroupMarks(const GroupMarks&) = delete;
  GroupMarks& operator=(const GroupMarks&) = delete;
  ~GroupMarks() { held() = false; }

  // The index in the group of the body of sphere i, or -1 when i is not in the group.
  int body_index(int i) const {
    const std::uint64_t mark = marks_[cluster_of_sphere_[i]];
    return (mark & kStampBits) == stamp_ ? static_cast<int>(mark & ~kStampBits) : -1;
  }

 private:
  static constexpr std::uint64_t kStampBits = ~std::uint64_t{0xffffffff};  // the high half of a mark
  static constexpr std::uint64_t kStampsPerClear = std::uint64_t{1} << 32;
  static std::vector<std::uint64_t>& thread_marks() {
    thread_local std::vector<std::uint64_t> marks;
    return marks;
  }
  static std::uint64_t& thread_stamp() {
    thread_local std::uint64_t stamp = 0;
    return stamp;
  }
  static bool& held() {
    thread_local bool is_held = false;
    return is_held;
  }

  const std::int32_t* cluster_of_sphere_;
  std::vector<std::uint64_t>& marks_;
  std::uint64_t stamp_;
};

}  // namespace ballagg
