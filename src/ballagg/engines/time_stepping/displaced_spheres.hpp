#pragma once
// Spheres that moved farther than the cell slack since the step's cell list was built.
//
// Rebuilding the cell list costs O(N); within one step, the fall-back (retreat.hpp) runs
// group after group, and each may move spheres by up to the step's flight. Rebuilding
// before every one of them made the cost of a step grow like N times the number of
// retreats. Instead, a sphere moved beyond the slack is listed here: neighbour queries skip
// it in the cell list (where it is binned at a stale place) and visit every listed sphere
// besides. The cell list is rebuilt only when the list makes queries cost more than that.
#include <cstdint>
#include <vector>

namespace ballagg {

class DisplacedSpheres {
 public:
  void reset(int n) {
    list_.clear();
    flag_.assign(n, 0);
  }
  void clear() {
    for (std::int32_t i : list_) flag_[i] = 0;
    list_.clear();
  }
  void add(std::int32_t i) {
    if (flag_[i]) return;
    flag_[i] = 1;
    list_.push_back(i);
  }
  bool contains(std::int32_t i) const { return flag_[i] != 0; }
  const std::vector<std::int32_t>& list() const { return list_; }
  std::size_t size() const { return list_.size(); }

 private:
  std::vector<std::int32_t> list_;
  std::vector<char> flag_;
};

}  // namespace ballagg
