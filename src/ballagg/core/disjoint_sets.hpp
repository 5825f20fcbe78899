#pragma once
// Union–find over integer ids with path halving (find) and union by size. Ids are reset one by
// one (reset(id)), so a structure sized for every cluster can be reused cheaply by work
// that touches only a few ids.
#include <cstdint>
#include <utility>
#include <vector>

namespace ballagg {

class DisjointSets {
 public:
  explicit DisjointSets(int n = 0) : parent_(n), size_(n, 1) {
    for (int i = 0; i < n; ++i) parent_[i] = i;
  }

  void reset(int id) {
    parent_[id] = id;
    size_[id] = 1;
  }

  // The root of id's set without shortening the path on the way, so that threads may ask
  // together; union by size keeps paths O(log n) long.
  int root(int id) const {
    while (parent_[id] != id) id = parent_[id];
    return id;
  }

  int find(int id) {
    while (parent_[id] != id) {
      parent_[id] = parent_[parent_[id]];
      id = parent_[id];
    }
    return id;
  }

  // Joins the sets of a and b; returns the new root.
  int unite(int a, int b) { return unite_roots(find(a), find(b)); }

  // Joins the sets whose roots are a and b: the larger (of equal sizes, the lower id)
  // stays the root, which is returned.
  int unite_roots(int a, int b) {
    if (a == b) return a;
    if (size_[a] < size_[b] || (size_[a] == size_[b] && b < a)) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
    return a;
  }

 private:
  std::vector<std::int32_t> parent_;
  std::vector<std::int32_t> size_;
};

}  // namespace ballagg
