#pragma once
// Where the spheres of the step are, and the cell list they are binned in, kept from one
// step to the next.
//
// Positions are computed when a stage first needs them (a step in which nothing comes near
// reads only the listed near pairs). The cell list is not rebuilt at every step: a cluster
// carries a bound on how far its spheres have drifted since they were binned, and a
// sphere may be up to the cell slack from where it is binned; queries look that much
// wider. At a step's first use the clusters that drifted beyond kBinnedDrift of the slack
// are binned again, and the whole list is rebuilt when too many spheres have been moved
// in it one by one.
#include <algorithm>
#include <optional>
#include <vector>

#include "ballagg/core/state.hpp"
#include "ballagg/engines/time_stepping/near_pairs.hpp"
#include "ballagg/spatial/movable_cell_list.hpp"

namespace ballagg {

template <int D>
class StepCells {
 public:
  // Cells (2 + kGridMargin) R_max wide, for the state's spheres and cluster ids.
  void reset(const State<D>& s);

  // The step's positions are those of s at its time, computed on first need.
  void defer_positions(const State<D>& s) {
    positions_of_ = &s;
    binned_ = false;
  }
  void materialise();
  void materialise(const std::vector<std::int32_t>& spheres);
  std::vector<Vec<D>>& positions() { return positions_; }
  const std::vector<Vec<D>>& positions() const { return positions_; }

  const MovableCellList<D>& list() const { return *cells_; }
  MovableCellList<D>& list() { return *cells_; }
  double slack() const { return slack_; }
  // The list with every sphere within kBinnedDrift of the slack of where it is binned.
  const MovableCellList<D>& binned(const State<D>& s);
  // The list for `queries` queries of a partial refresh of the near pairs (skin: the near
  // list's), perhaps looking wider instead of binning the drifted clusters again.
  typename NearPairCells<D>::Binned for_queries(const State<D>& s, std::size_t queries, double skin);
  // Bins every sphere at its position now.
  void rebin();

  // Cluster c's spheres moved by `distance` together (free flight).
  void drifted(int c, double distance) { drift_[c] += distance; }
  // Sphere i, of cluster c, moved by `shift` in a minimisation; true when it is now beyond
  // the slack of where it is binned (then move_in_list before the next query).
  bool moved(int i, int c, const Vec<D>& shift) {
    moved_[i] += shift;
    return drift_[c] + moved_[i].norm() > slack_;
  }
  void move_in_list(int i) {
    cells_->move(i, positions_[i]);
    moved_[i].setZero();
  }
  void rebin_if_many_moved();

  // At commit: the moves of sphere i since binned, read and forgotten; the largest of each
  // moved cluster joins its drift (commit_drifts).
  const std::vector<Vec<D>>& moves_since_binned() const { return moved_; }
  double move_since_binned(int i) const { return moved_[i].norm(); }
  void forget_move(int i) { moved_[i].setZero(); }
  void cluster_moved(int c, double largest, std::vector<std::int32_t>& moved_clusters) {
    if (committed_[c] == 0.0) moved_clusters.push_back(c);
    committed_[c] = std::max(committed_[c], largest);
  }
  void commit_drifts(const std::vector<std::int32_t>& moved_clusters) {
    for (std::int32_t c : moved_clusters) {
      drift_[c] += committed_[c];
      committed_[c] = 0.0;
    }
  }
  void merged(int ci, int cj, int into) { drift_[into] = std::max(drift_[ci], drift_[cj]); }

 private:
  std::vector<Vec<D>> positions_;           // sphere centres at the step's time, in the box
  const State<D>* positions_of_ = nullptr;  // set: positions_ not yet computed for this step
  std::vector<Vec<D>> moved_;               // per sphere: this step's moves since it was binned
  std::vector<double> drift_;               // per cluster id: bound on its spheres' moves since binned, before this step's minimisations
  std::vector<double> committed_;           // per cluster id, within commit: largest move of a sphere since binned
  std::optional<MovableCellList<D>> cells_;
  double slack_ = 0.0;                      // how far a sphere may move before it is binned again
  bool built_ = false;                      // the list has been built since reset
  bool binned_ = false;                     // every sphere is within the slack of where it is binned
  double wide_query_cells_ = 0.0;           // cells visited by widened queries since the list was built
};

extern template class StepCells<2>;
extern template class StepCells<3>;

}  // namespace ballagg
