#pragma once
// The overlap detection of a time step (step 2a of §3) without a scan of the whole box at
// every step.
//
// Clusters only translate between two detections (free flight, wall mirroring, and what
// the minimisations moved them), so the distance between two spheres of different
// clusters changes by at most what the two clusters travelled. The list keeps every pair
// of spheres of different clusters closer than sigma + skin, and for each cluster how far
// it has travelled since its pairs were listed (an upper bound for each of its spheres).
// While two clusters have both travelled at most skin / 2, every pair of theirs that
// overlaps now is in the list. A cluster that travelled more is *stale*: its pairs are
// listed again from a cell list, by queries around its spheres or, when one stale cluster
// holds most of the box, around the spheres outside it (the cell list may have binned the
// spheres at an earlier step: the queries look wider by how far they may have moved
// since). Late in a run, when a few large, slow clusters hold most spheres, a step then
// costs the few fast clusters' spheres and the listed pairs, instead of every sphere of
// the box; and when the giant drifts beyond the skin, the spheres outside it. The pairs
// found are exactly those a scan of the whole box finds.
#include <cstdint>
#include <functional>
#include <vector>

#include "ballagg/core/state.hpp"
#include "ballagg/engines/time_stepping/adhesive_set.hpp"
#include "ballagg/spatial/movable_cell_list.hpp"
#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {

// The cell lists NearPairs::contacts() may ask for; each first fills every entry of the
// positions it was given.
template <int D>
struct NearPairCells {
  // Every sphere binned afresh at its position (for a scan of the whole box).
  std::function<const SortedCellList<D>&()> rebuilt;
  // A cell list in which every sphere is within `slack` of where it is binned, for the
  // queries of a partial refresh (which look that much wider), given how many spheres they
  // will be made around. With lazy_positions the positions passed to contacts() have not
  // been filled: the refresh reads them from the state (State::position at its time), and
  // `need` is called for the spheres of the listed pairs before they are tested.
  struct Binned {
    const MovableCellList<D>& list;
    double slack;
    bool lazy_positions = false;
  };
  std::function<Binned(std::size_t queries)> current;
};

template <int D>
class NearPairs {
 public:
  NearPairs() = default;
  // `skin` must not exceed the cell size of the cell lists passed to contacts() minus the
  // largest contact distance: pairs closer than sigma + skin are then in neighbouring cells
  // of a list rebuilt at the positions.
  NearPairs(int n_cluster_ids, double skin);

  // Cluster c moved by a displacement of this length (free flight, a wall).
  void travelled(int c, double distance) { travel_[c] += distance; }
  // A sphere of cluster c was moved by this much by the minimisations of the step; the
  // largest over the cluster's spheres counts, at the next flush_shifts().
  void shifted(int c, double distance);
  void flush_shifts();
  // Clusters a and b merged into `into`: each sphere of it travelled at most the larger.
  void merged(int a, int b, int into);

  // Lists the pairs of the stale clusters again, with the spheres at `positions`, and
  // returns every pair of spheres of different clusters that overlaps or touches
  // (d <= R_i + R_j), sorted by (i, j). A cell list of `cells` is asked for only when some
  // cluster is stale. Otherwise only the spheres of the listed pairs are read, and
  // `need(spheres)` is called first with them (the caller fills their entries of
  // `positions` then).
  std::vector<SpherePair> contacts(const State<D>& s, const std::vector<Vec<D>>& positions,
                                   const NearPairCells<D>& cells,
                                   const std::function<void(const std::vector<std::int32_t>&)>& need);

  // Whether sphere i is in a pair of the list as the last contacts() left it. Until a
  // cluster has moved more than skin / 2 since its pairs were listed (travel() plus what
  // the step's minimisations have moved it since contacts()), a sphere that is in no pair
  // is farther than its contact distance from every sphere of another cluster.
  bool listed(int i) const { return listed_at_[i] == listing_; }
  double travel(int c) const { return travel_[c]; }
  double skin() const { return skin_; }

  // Detections that scanned the whole box (the first, and those that would otherwise have
  // queried more than kFullScanFraction of the spheres), those that refreshed a part, and
  // of these the ones that queried the spheres outside the largest stale cluster.
  std::int64_t full_scans() const { return full_scans_; }
  std::int64_t partial_scans() const { return partial_scans_; }
  std::int64_t outside_scans() const { return outside_scans_; }

 private:
  struct Pair {
    std::int32_t i, j;  // i < j
  };
  bool stale(int c) const { return !(travel_[c] <= 0.5 * skin_); }
  void scan_all(const State<D>& s, const SortedCellList<D>& cells);
  std::vector<SpherePair> test_listed(const State<D>& s, const std::vector<Vec<D>>& positions);
  void refresh(const State<D>& s, const typename NearPairCells<D>::Binned& cells, const std::vector<Vec<D>>& positions,
               const std::vector<char>& is_stale, const std::vector<char>& queried,
               const std::vector<int>& query_spheres);
  std::vector<std::int32_t> listed_spheres() const;

  double skin_ = 0.0;
  std::vector<double> travel_;        // per cluster id; +inf before the first listing
  std::vector<double> step_shift_;    // per cluster id: largest shift of a sphere this step
  std::vector<std::int32_t> shifted_; // clusters with a non-zero step_shift_
  std::vector<Pair> pairs_;           // sorted by (i, j)
  std::vector<std::int32_t> listed_at_;  // per sphere: the last contacts() that found it in a pair
  std::int32_t listing_ = 0;             // contacts() calls so far
  std::int64_t full_scans_ = 0, partial_scans_ = 0, outside_scans_ = 0;
};

}  // namespace ballagg
