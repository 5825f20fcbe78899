#pragma once
// The adhesive links of the non-rigid and almost-rigid models: which pairs of spheres of
// a cluster are bonded, with the Lagrange multiplier of their non-overlap constraint kept
// from one minimisation to the next (a warm start: at equilibrium a link of the non-rigid
// model carries lambda = 1/2, which balances its attraction exactly, so an undisturbed
// part of an old cluster feels no force). Stored per sphere, under the lower id.
#include <cstdint>
#include <utility>
#include <vector>

namespace ballagg {

struct LinkEnd {
  std::int32_t other;  // the higher sphere id of the pair
  double lambda;
};

class AdhesiveLinks {
 public:
  explicit AdhesiveLinks(int n_spheres = 0) : by_sphere_(n_spheres) {}

  // Links (i, other) with other > i.
  const std::vector<LinkEnd>& of(int i) const { return by_sphere_[i]; }
  std::vector<LinkEnd>& of(int i) { return by_sphere_[i]; }

  double* find(int i, int j) {
    if (i > j) std::swap(i, j);
    for (LinkEnd& e : by_sphere_[i])
      if (e.other == j) return &e.lambda;
    return nullptr;
  }
  bool linked(int i, int j) const { return const_cast<AdhesiveLinks*>(this)->find(i, j) != nullptr; }

  void add(int i, int j, double lambda) {
    if (i > j) std::swap(i, j);
    if (double* l = find(i, j)) { *l = lambda; return; }
    by_sphere_[i].push_back({j, lambda});
    ++count_;
  }
  std::int64_t size() const { return count_; }

 private:
  std::vector<std::vector<LinkEnd>> by_sphere_;
  std::int64_t count_ = 0;
};

}  // namespace ballagg
