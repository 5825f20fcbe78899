#include "ballagg/engines/time_stepping/step_cells.hpp"

#include <algorithm>
#include <cmath>

#include "ballagg/core/parallel.hpp"

namespace ballagg {
namespace {

// Cells are (2 + kGridMargin) R_max wide: spheres may move by kGridMargin R_max during the
// minimisations before they must be binned again.
constexpr double kGridMargin = 1.0;

// The list is rebuilt once more than 1 / kMovedFractionForRebuild of the spheres have been
// moved in it one by one (each move leaves a skipped slot behind).
constexpr std::size_t kMovedFractionForRebuild = 8;

// A cluster is binned again at a step's first use once it has drifted more than this
// fraction of the slack since it was binned; the others keep the rest of the slack for the
// step's minimisations. Binning only the drifted clusters spares a rebuild at every step
// in which a few fragments move while a large cluster drifts slowly.
constexpr double kBinnedDrift = 0.75;

// Widened queries are made while the cells they visit since the list was built number
// fewer than 1 / kWideQueryShare of the spheres (what a rebuild costs), so that they never
// cost much more than binning the drifted clusters again.
constexpr double kWideQueryShare = 8.0;

}  // namespace

template <int D>
void StepCells<D>::reset(const State<D>& s) {
  const int n = s.n_spheres();
  const std::size_t n_cluster_ids = s.clusters.size();
  positions_.resize(n);
  positions_of_ = nullptr;
  moved_.assign(n, Vec<D>::Zero());
  drift_.assign(n_cluster_ids, 0.0);
  committed_.assign(n_cluster_ids, 0.0);
  built_ = false;
  cells_.emplace(s.box, (2.0 + kGridMargin) * s.max_radius(), n);
  slack_ = cells_->cell_size() - 2.0 * s.max_radius();
}

// Every sphere's position at the step's time (what defer_positions put off).
template <int D>
void StepCells<D>::materialise() {
  if (positions_of_ == nullptr) return;
  const State<D>& s = *positions_of_;
  const int n = s.n_spheres();
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
  for (int i = 0; i < n; ++i) positions_[i] = s.position(i, s.time);
  positions_of_ = nullptr;
}

// The positions of these spheres only (the same values: State::position at the step's time).
template <int D>
void StepCells<D>::materialise(const std::vector<std::int32_t>& spheres) {
  if (positions_of_ == nullptr) return;
  for (std::int32_t i : spheres) positions_[i] = positions_of_->position(i, positions_of_->time);
}

// The spheres of the clusters that drifted more than kBinnedDrift of the slack are binned
// again, or, when they are many, every sphere.
template <int D>
const MovableCellList<D>& StepCells<D>::binned(const State<D>& s) {
  if (binned_) return *cells_;
  materialise();
  std::vector<int> drifted;
  std::size_t to_move = cells_->n_moved();
  if (built_)
    for (int c : s.alive_clusters())
      if (drift_[c] > kBinnedDrift * slack_) {
        drifted.push_back(c);
        to_move += static_cast<std::size_t>(s.clusters[c].size());
      }
  if (!built_ || to_move * kMovedFractionForRebuild > positions_.size()) {
    rebin();
    return *cells_;
  }
  for (int c : drifted) {
    for (int i : s.clusters[c].members) cells_->move(i, positions_[i]);
    drift_[c] = 0.0;
  }
  binned_ = true;
  return *cells_;
}

// A few queries look wider, by the largest drift of a cluster since it was binned, instead
// of binning the drifted clusters again: the queries around the few spheres outside a
// large drifted cluster then do not cost a rebuild of the whole list. The list is left as
// it is: the step's later stages bin what they need (binned). The pairs found are the same
// either way.
template <int D>
typename NearPairCells<D>::Binned StepCells<D>::for_queries(const State<D>& s, std::size_t queries, double skin) {
  if (built_ && !binned_) {
    double drift = kBinnedDrift * slack_;
    for (int c : s.alive_clusters()) drift = std::max(drift, drift_[c]);
    // The cells the widened queries visit, against a rebuild's passes over every sphere.
    const double reach = (2.0 * s.max_radius() + skin + drift) / cells_->cell_size();
    const double cells = static_cast<double>(queries) * std::pow(2.0 * std::ceil(reach) + 1.0, D);
    if ((wide_query_cells_ + cells) * kWideQueryShare <= static_cast<double>(s.n_spheres())) {
      wide_query_cells_ += cells;
      // Nor are the positions of every sphere filled for so few queries.
      return {*cells_, drift, positions_of_ != nullptr};
    }
  }
  return {binned(s), kBinnedDrift * slack_, false};
}

template <int D>
void StepCells<D>::rebin() {
  materialise();
  cells_->build(positions_);
  built_ = binned_ = true;
  wide_query_cells_ = 0.0;
  std::fill(moved_.begin(), moved_.end(), Vec<D>::Zero());
  std::fill(drift_.begin(), drift_.end(), 0.0);
}

template <int D>
void StepCells<D>::rebin_if_many_moved() {
  if (cells_->n_moved() * kMovedFractionForRebuild > positions_.size()) rebin();
}

template class StepCells<2>;
template class StepCells<3>;

}  // namespace ballagg
