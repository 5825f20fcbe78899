#pragma once
// The bodies of one time step. A step starts with the clusters of the state, each a body of
// its own. A round of the loop (3.1)-(3.2) that leaves two spheres of different bodies
// touching links them: from the next round on the two bodies move as one (rigid model:
// one variable), so every problem stays as small as what is new. Nothing changes in the
// state before the step ends; then the links merge their clusters (rule 2.9).
//
// A body is only a grouping, so it can be dissolved again into the clusters it is made of
// (its links go back to S): when a later round finds an overlap inside it, or when a
// minimisation fails and its group is moved back along its flight, where each cluster
// retreats along its own.
//
// The lists per body are sized for every cluster id and held by the few touched ones: they
// live in pools (core/pooled_lists.hpp), 8 bytes per id and list.
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "ballagg/core/disjoint_sets.hpp"
#include "ballagg/core/pooled_lists.hpp"
#include "ballagg/engines/time_stepping/adhesive_set.hpp"

namespace ballagg {

class StepBodies {
 public:
  explicit StepBodies(int n_cluster_ids = 0) { reset(n_cluster_ids); }

  // Every cluster of n_cluster_ids a body of its own; the pools' memory is released.
  void reset(int n_cluster_ids) {
    sets_ = DisjointSets(n_cluster_ids);
    clusters_.reset(n_cluster_ids);
    links_.reset(n_cluster_ids);
    touched_ = {};
    touched_mark_.assign(n_cluster_ids, 0);
  }

  // The body of cluster c, named by its root cluster. Does not modify the structure, so
  // threads may call it together (union by size keeps the paths short).
  int body_of(int c) const { return sets_.root(c); }
  // The clusters of a body (its root): the root alone when nothing was linked to it.
  std::vector<std::int32_t> clusters_of(int body) const {
    if (clusters_.empty(body)) return {body};
    return {clusters_.begin(body), clusters_.end(body)};
  }
  std::span<const SpherePair> links_of(int body) const { return {links_.begin(body), links_.end(body)}; }

  // Links the spheres i (of cluster ci) and j (of cluster cj): joins their bodies.
  void link(const SpherePair& p, int ci, int cj) {
    int a = body_of(ci), b = body_of(cj);
    touch(a);
    touch(b);
    if (a != b) {
      if (sets_.unite_roots(a, b) == b) std::swap(a, b);
      clusters_.append_owner(a, b);
      links_.append_owner(a, b);
    }
    links_.push_back(a, p);
  }

  // Splits a body back into its clusters; returns the links it held.
  std::vector<SpherePair> dissolve(int body) {
    std::vector<SpherePair> links(links_.begin(body), links_.end(body));
    const std::vector<std::int32_t> clusters = clusters_of(body);
    for (int c : clusters) {
      sets_.reset(c);
      clusters_.assign(c, &c, 1);
      links_.release(c);
    }
    return links;
  }

  // Every link of the step, in the order they were made within each body, bodies in
  // increasing order of their root.
  std::vector<SpherePair> all_links() const {
    std::vector<std::int32_t> roots;
    for (int c : touched_)
      if (sets_.root(c) == c) roots.push_back(c);
    std::sort(roots.begin(), roots.end());
    std::vector<SpherePair> out;
    for (int r : roots) out.insert(out.end(), links_.begin(r), links_.end(r));
    return out;
  }

  // Every cluster back to a body of its own, at the cost of what the step touched.
  void clear() {
    for (int c : touched_) {
      sets_.reset(c);
      clusters_.release(c);
      links_.release(c);
      touched_mark_[c] = 0;
    }
    touched_.clear();
  }

 private:
  void touch(int root) {
    if (touched_mark_[root]) return;
    touched_mark_[root] = 1;
    touched_.push_back(root);
    if (clusters_.empty(root)) clusters_.push_back(root, root);
  }

  DisjointSets sets_;                                // the bodies, as sets of cluster ids
  PooledLists<std::int32_t> clusters_;               // per root: its clusters (empty: just itself)
  PooledLists<SpherePair> links_;                    // per root: its links
  std::vector<std::int32_t> touched_;                // clusters whose entries are not pristine
  std::vector<char> touched_mark_;
};

}  // namespace ballagg
