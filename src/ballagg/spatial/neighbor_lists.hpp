#pragma once
// Verlet-style lists of *foreign* neighbours: for each sphere, the spheres of other clusters
// whose bins (where the engine last put them on its cell grid) are within sigma + skin of
// its own bin. Which pairs belong is the engine's decision (neighbor_keeper.hpp).
// Spheres of the same cluster never collide (clusters are rigid), so they are never listed.
//
// Each cluster also keeps its "exposed" spheres: those with at least one foreign neighbour.
// When a cluster's velocity changes, only its exposed spheres need new collision
// predictions; the interior of a big aggregate costs nothing.
#include <cstdint>
#include <span>
#include <vector>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/pooled_lists.hpp"
#include "ballagg/core/small_vector.hpp"

namespace ballagg {

class NeighborLists {
 public:
  void reset(int n_spheres, int n_clusters) {
    partners_.reset(n_spheres);
    slot_.assign(n_spheres, -1);
    exposed_.assign(n_clusters, {});
  }

  std::span<const std::int32_t> partners(int sphere) const {
    return {partners_.begin(sphere), partners_.size(sphere)};
  }
  std::span<const std::int32_t> exposed(int cluster) const { return exposed_[cluster]; }

  // cluster_of[k] is the current cluster id of sphere k.
  void add_pair(int i, int j, const std::int32_t* cluster_of) {
    add_partner(i, j, cluster_of);
    add_partner(j, i, cluster_of);
  }

  bool listed(int i, int j) const {
    for (std::int32_t p : partners(i))
      if (p == j) return true;
    return false;
  }

  void remove_pair(int i, int j, const std::int32_t* cluster_of) {
    erase_partner(i, j);
    if (partners_.empty(i)) unexpose(i, cluster_of[i]);
    erase_partner(j, i);
    if (partners_.empty(j)) unexpose(j, cluster_of[j]);
  }

  void remove_all_pairs(int i, const std::int32_t* cluster_of) {
    for (std::int32_t j : partners(i)) {
      erase_partner(j, i);
      if (partners_.empty(j)) unexpose(j, cluster_of[j]);
    }
    partners_.clear(i);
    if (slot_[i] >= 0) unexpose(i, cluster_of[i]);
  }

  // Drops the last sphere's list, emptied before (remove_all_pairs): ids stay dense when a
  // sphere leaves for good.
  void pop_back() {
    partners_.pop_owner();
    slot_.pop_back();
  }

  // After the spheres of cluster `gone` were relabelled as members of `keep`: drops the
  // pairs that became internal and hands gone's exposed spheres over to keep.
  void absorb(int keep, int gone, const std::int32_t* cluster_of) {
    const Exposed handed = std::move(exposed_[gone]);
    for (std::int32_t s : handed) {
      // Erasing s from its partners' lists moves no block: `ps` stays valid.
      std::int32_t* ps = partners_.begin(s);
      for (std::uint32_t k = 0; k < partners_.size(s);) {
        const std::int32_t p = ps[k];
        if (cluster_of[p] != keep) { ++k; continue; }
        erase_partner(p, s);
        if (partners_.empty(p)) unexpose(p, keep);
        ps[k] = ps[partners_.size(s) - 1];
        partners_.pop_back(s);
      }
      if (partners_.empty(s)) {
        slot_[s] = -1;
      } else {
        slot_[s] = static_cast<std::int32_t>(exposed_[keep].size());
        exposed_[keep].push_back(s);
      }
    }
  }

  std::size_t pair_count() const {
    std::size_t n = 0;
    for (int i = 0; i < partners_.owners(); ++i) n += partners_.size(i);
    return n / 2;
  }

  // Checkpoints: every list in its order; restore() into lists reset() to the same sizes.
  void save(ByteWriter& w) const {
    for (int i = 0; i < partners_.owners(); ++i) w.put_array(partners_.begin(i), partners_.size(i));
    for (const Exposed& e : exposed_) w.put_array(e.data(), static_cast<std::size_t>(e.size()));
  }
  void restore(ByteReader& r) {
    const int n = partners_.owners();
    for (int i = 0; i < n; ++i) {
      const std::vector<std::int32_t> p = r.get_vector<std::int32_t>("neighbour list", static_cast<std::uint64_t>(n));
      for (std::int32_t j : p)
        if (j < 0 || j >= n) r.fail("neighbour list names no sphere");
      partners_.assign(i, p.data(), p.size());
    }
    for (Exposed& e : exposed_) {
      r.get_into<std::int32_t>(e, "exposed spheres", static_cast<std::uint64_t>(n));
      for (std::int32_t k = 0; k < e.size(); ++k) {
        const std::int32_t i = e[k];
        if (i < 0 || i >= n || slot_[i] >= 0 || partners_.empty(i)) r.fail("exposed spheres inconsistent with the lists");
        slot_[i] = k;
      }
    }
  }

 private:
  void add_partner(int i, int j, const std::int32_t* cluster_of) {
    if (partners_.empty(i)) {
      const int c = cluster_of[i];
      slot_[i] = static_cast<std::int32_t>(exposed_[c].size());
      exposed_[c].push_back(i);
    }
    partners_.push_back(i, j);
  }
  void erase_partner(int i, int j) {
    std::int32_t* ps = partners_.begin(i);
    const std::uint32_t n = partners_.size(i);
    for (std::uint32_t k = 0; k < n; ++k) {
      if (ps[k] == j) {
        ps[k] = ps[n - 1];
        partners_.pop_back(i);
        return;
      }
    }
  }
  void unexpose(int i, int cluster) {
    Exposed& ex = exposed_[cluster];
    const std::int32_t last = ex.back();
    ex[slot_[i]] = last;
    slot_[last] = slot_[i];
    ex.pop_back();
    slot_[i] = -1;
  }

  // A sphere has about kSkinNeighbours partners (about 12 in a dense gas, none inside a
  // big aggregate): each list is a block of 2^k in a pool, behind an 8-byte handle. A
  // monomer has at most one exposed sphere; big clusters spill to the heap.
  using Exposed = SmallVector<std::int32_t, 2>;
  PooledLists<std::int32_t> partners_;
  std::vector<Exposed> exposed_;
  std::vector<std::int32_t> slot_;  // position of a sphere in its cluster's exposed list, or -1
};

}  // namespace ballagg
