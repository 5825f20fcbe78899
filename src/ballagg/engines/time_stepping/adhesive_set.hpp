#pragma once
// The adhesive set S of one round of the loop (3.1)-(3.2) (paper §3, step 2) and the
// groups it joins: pairs of spheres, each with the Lagrange multiplier of its constraint,
// and the connected groups of bodies they join (each an independent minimisation problem),
// kept by union–find as pairs are added, each root holding the lists of its bodies and
// pairs. Bodies are named by a cluster id (step_bodies.hpp); clearing costs the size of S.
//
// The lists are sized for every cluster id but held by the few roots: they live in pools
// (core/pooled_lists.hpp), 8 bytes per id and list, where a std::vector per id would cost
// its 24-byte header and keep the block of every list it ever held.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "ballagg/core/disjoint_sets.hpp"
#include "ballagg/core/pair_index.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/core/pooled_lists.hpp"
#include "ballagg/core/prefetch.hpp"

namespace ballagg {

struct SpherePair {
  std::int32_t i, j;  // sphere ids, i < j
  double lambda;      // multiplier of its constraint (0: not set yet, (3.26) applies)
};

// The order of pairs (of anything with sphere ids i, j) by i, then j: lists of pairs are
// sorted so that they do not depend on the order a search (or its threads) found them in.
template <class Pair>
bool pair_less(const Pair& a, const Pair& b) {
  return a.i != b.i ? a.i < b.i : a.j < b.j;
}

// One connected group: the bodies (named by a cluster id) and the pairs of S that join them.
struct CollisionGroup {
  std::vector<std::int32_t> bodies;  // sorted
  std::vector<std::int32_t> pairs;   // indices into S, sorted
};

class AdhesiveSet {
 public:
  explicit AdhesiveSet(int n_cluster_ids = 0) { reset(n_cluster_ids); }

  // An empty set for n_cluster_ids ids; the pools' memory is released.
  void reset(int n_cluster_ids) {
    pairs_ = {};
    index_ = PairIndex();
    sets_ = DisjointSets(n_cluster_ids);
    clusters_of_.reset(n_cluster_ids);
    pairs_of_.reset(n_cluster_ids);
    touched_ = {};
    touched_mark_.assign(n_cluster_ids, 0);
    changed_ = {};
    changed_mark_.assign(n_cluster_ids, 0);
  }

  const std::vector<SpherePair>& pairs() const { return pairs_; }
  SpherePair& pair(std::int32_t k) { return pairs_[k]; }
  bool empty() const { return pairs_.empty(); }
  // Room for n more pairs.
  void reserve(std::size_t n) {
    index_.reserve(pairs_.size() + n);
    pairs_.reserve(pairs_.size() + n);
  }
  bool contains(int i, int j) const { return index_.find(i, j) != PairIndex::kAbsent; }

  // Adds the pair of spheres (i, j) of bodies ci and cj (one body is allowed: in the
  // per-sphere models a cluster can fold onto itself) unless it is in S already, and marks
  // its group as changed. Returns whether it was added.
  bool add(int i, int j, int ci, int cj) {
    if (i > j) { std::swap(i, j); std::swap(ci, cj); }
    const auto [k, added] = index_.insert(i, j, static_cast<std::int32_t>(pairs_.size()));
    if (!added) return false;
    pairs_.push_back({i, j, 0.0});
    touch(ci);
    touch(cj);
    const int a = sets_.find(ci), b = sets_.find(cj);
    const int root = sets_.unite(a, b);
    if (a != b) {
      const int other = root == a ? b : a;
      move_append(clusters_of_, other, root);
      move_append(pairs_of_, other, root);
    }
    pairs_of_.push_back(root, k);
    mark_changed(root);
    return true;
  }

  // add() for each pair (i, j) in order, of bodies cluster_of[i] and cluster_of[j]. The
  // same as the adds one by one; the slot of a pair in the index is asked for
  // kPrefetchAhead pairs ahead (the first step of a large run adds millions of pairs to a
  // table far larger than the cache, and each add would wait for its slot from memory).
  void add_all(const std::vector<SpherePair>& pairs, const std::vector<std::int32_t>& cluster_of) {
    reserve(pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (k + kPrefetchAhead < pairs.size()) index_.prefetch(pairs[k + kPrefetchAhead].i, pairs[k + kPrefetchAhead].j);
      const SpherePair& p = pairs[k];
      add(p.i, p.j, cluster_of[p.i], cluster_of[p.j]);
    }
  }

  // The groups that changed since the last call, each once, in the order of their lowest
  // cluster id (the same order whatever the number of threads).
  std::vector<CollisionGroup> take_changed_groups() {
    std::vector<CollisionGroup> out;
    for (int c : changed_) changed_mark_[c] = 0;
    std::vector<int> roots;
    for (int c : changed_) {
      const int r = sets_.find(c);
      if (!changed_mark_[r]) {
        changed_mark_[r] = 1;
        roots.push_back(r);
      }
    }
    for (int r : roots) changed_mark_[r] = 0;
    changed_.clear();
    // Each group copied and sorted apart, on the threads (the first round of a large run
    // takes a group per few spheres), then put in order.
    const std::int64_t n = static_cast<std::int64_t>(roots.size());
    std::vector<CollisionGroup> unordered(roots.size());
    std::vector<std::pair<std::int32_t, std::int32_t>> order(roots.size());  // (lowest body, k)
#pragma omp parallel for schedule(dynamic, 256) if (n >= kParallelLoopMin)
    for (std::int64_t k = 0; k < n; ++k) {
      CollisionGroup& g = unordered[k];
      g.bodies.assign(clusters_of_.begin(roots[k]), clusters_of_.end(roots[k]));
      g.pairs.assign(pairs_of_.begin(roots[k]), pairs_of_.end(roots[k]));
      std::sort(g.bodies.begin(), g.bodies.end());
      std::sort(g.pairs.begin(), g.pairs.end());
      order[k] = {g.bodies.front(), static_cast<std::int32_t>(k)};
    }
    std::sort(order.begin(), order.end());  // groups are disjoint: their lowest bodies differ
    out.reserve(roots.size());
    for (const auto& [lowest, k] : order) out.push_back(std::move(unordered[k]));
    return out;
  }

  // Empties S for the next step: costs the size of S, not the number of clusters.
  void clear() {
    for (int c : touched_) {
      sets_.reset(c);
      clusters_of_.release(c);
      pairs_of_.release(c);
      touched_mark_[c] = 0;
    }
    touched_.clear();
    changed_.clear();
    pairs_.clear();
    index_.clear();
  }

 private:
  void touch(int c) {
    if (touched_mark_[c]) return;
    touched_mark_[c] = 1;
    touched_.push_back(c);
    clusters_of_.push_back(c, c);
  }
  void mark_changed(int root) {
    if (changed_mark_[root]) return;
    changed_mark_[root] = 1;
    changed_.push_back(root);
  }
  // Moves owner from's list into owner to's, copying the shorter of the two.
  static void move_append(PooledLists<std::int32_t>& lists, int from, int to) {
    if (lists.size(from) > lists.size(to)) lists.swap_owners(from, to);
    lists.append_owner(to, from);
  }

  std::vector<SpherePair> pairs_;
  PairIndex index_;
  DisjointSets sets_;
  PooledLists<std::int32_t> clusters_of_;               // per root: the clusters of its group
  PooledLists<std::int32_t> pairs_of_;                  // per root: its pairs (indices into pairs_)
  std::vector<std::int32_t> touched_;                   // clusters with a pair in S
  std::vector<char> touched_mark_;
  std::vector<std::int32_t> changed_;                   // roots (at the time) of changed groups
  std::vector<char> changed_mark_;
};

}  // namespace ballagg
