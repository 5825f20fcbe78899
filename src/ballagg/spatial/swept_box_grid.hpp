#pragma once
// Which of many moving bodies can meet, without testing every pair of them.
//
// Each body sweeps a box: the box around its path, widened by what counts as meeting (for
// a sphere moving along a segment: its radius and half a contact distance). Two bodies
// that meet at some instant are then at that instant inside boxes that overlap, so the
// bodies whose boxes share a cell of a grid over the boxes are a superset of those that
// can meet, and an exact test picks among them at a cost that follows the number of bodies
// instead of its square. The retreats of the time-stepping engine find the clusters of a
// large group that can meet this way (engines/time_stepping/retreat.cpp).
//
// With periodic faces the grid spans the box and a cell index wraps: a body that meets
// another meets one of its images, and every image of a box covers the same cells modulo
// the grid. Boxes covering more than kMaxCellsPerBox cells (a large body, a long path) are
// not put in the grid: they are candidates of every body.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

template <int D>
struct SweptBox {
  Vec<D> lo, hi;
};

template <int D>
class SweptBoxGrid {
 public:
  // Boxes covering more than this many cells are candidates of every box.
  static constexpr std::int64_t kMaxCellsPerBox = 64;
  // The grid has at most about this many cells per box.
  static constexpr double kCellsPerBox = 2.0;

  SweptBoxGrid(const Box<D>& box, const std::vector<SweptBox<D>>& boxes) : periodic_(box.periodic()), boxes_(boxes) {
    choose_cells(box);
    fill();
  }

  // Calls f(m) for every box m that may overlap box k (m = k among them), possibly more
  // than once.
  template <class F>
  void for_each_candidate(std::size_t k, F&& f) const {
    for (std::int32_t m : wide_) f(m);
    if (is_wide_[k]) {
      for (std::size_t m = 0; m < boxes_.size(); ++m) f(static_cast<std::int32_t>(m));
      return;
    }
    for_each_cell(k, [&](std::int64_t cell) {
      for (std::int64_t q = first_[cell]; q < first_[cell + 1]; ++q) f(entries_[q]);
    });
  }

 private:
  // The cell size: the median box's widest side, coarser if the grid would have more than
  // kCellsPerBox cells per box. With periodic faces, a whole number of cells spans the box.
  void choose_cells(const Box<D>& box) {
    const std::size_t n = boxes_.size();
    origin_ = boxes_.empty() ? Vec<D>::Zero() : boxes_.front().lo;
    Vec<D> top = origin_;
    std::vector<double> widest(n);
    for (std::size_t k = 0; k < n; ++k) {
      widest[k] = (boxes_[k].hi - boxes_[k].lo).maxCoeff();
      origin_ = origin_.cwiseMin(boxes_[k].lo);
      top = top.cwiseMax(boxes_[k].hi);
    }
    std::nth_element(widest.begin(), widest.begin() + static_cast<std::ptrdiff_t>(n / 2), widest.end());
    const Vec<D> extent = periodic_ ? Vec<D>::Constant(box.length) : Vec<D>(top - origin_);
    if (periodic_) origin_ = Vec<D>::Zero();
    const double cells_wanted = kCellsPerBox * static_cast<double>(std::max<std::size_t>(n, 1));
    double size = std::max(n > 0 ? widest[n / 2] : 1.0, std::pow(extent.prod() / cells_wanted, 1.0 / D));
    if (!(size > 0.0)) size = 1.0;
    for (int a = 0; a < D; ++a) {
      if (periodic_) {
        counts_[a] = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::floor(box.length / size)));
        cell_size_[a] = box.length / static_cast<double>(counts_[a]);
      } else {
        counts_[a] = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(extent[a] / size)));
        cell_size_[a] = size;
      }
    }
  }

  // The range of cell indices (unwrapped) that box k covers along each axis.
  void cell_range(std::size_t k, std::array<std::int64_t, D>& from, std::array<std::int64_t, D>& to) const {
    for (int a = 0; a < D; ++a) {
      from[a] = static_cast<std::int64_t>(std::floor((boxes_[k].lo[a] - origin_[a]) / cell_size_[a]));
      to[a] = static_cast<std::int64_t>(std::floor((boxes_[k].hi[a] - origin_[a]) / cell_size_[a]));
      if (periodic_ && to[a] - from[a] + 1 >= counts_[a]) {  // every cell along this axis
        from[a] = 0;
        to[a] = counts_[a] - 1;
      } else if (!periodic_) {
        from[a] = std::clamp<std::int64_t>(from[a], 0, counts_[a] - 1);
        to[a] = std::clamp<std::int64_t>(to[a], 0, counts_[a] - 1);
      }
    }
  }

  std::int64_t cells_covered(std::size_t k) const {
    std::array<std::int64_t, D> from, to;
    cell_range(k, from, to);
    std::int64_t cells = 1;
    for (int a = 0; a < D; ++a) cells *= to[a] - from[a] + 1;
    return cells;
  }

  template <class F>
  void for_each_cell(std::size_t k, F&& f) const {
    std::array<std::int64_t, D> from, to;
    cell_range(k, from, to);
    std::array<std::int64_t, D> at = from;
    while (true) {
      std::int64_t cell = 0;
      for (int a = D - 1; a >= 0; --a) {
        const std::int64_t wrapped = ((at[a] % counts_[a]) + counts_[a]) % counts_[a];
        cell = cell * counts_[a] + wrapped;
      }
      f(cell);
      int a = 0;
      while (a < D && at[a] == to[a]) at[a] = from[a], ++a;
      if (a == D) return;
      ++at[a];
    }
  }

  // The boxes of each cell, in increasing box order (a counting sort).
  void fill() {
    std::int64_t n_cells = 1;
    for (int a = 0; a < D; ++a) n_cells *= counts_[a];
    first_.assign(static_cast<std::size_t>(n_cells) + 1, 0);
    is_wide_.assign(boxes_.size(), 0);
    for (std::size_t k = 0; k < boxes_.size(); ++k) {
      if (cells_covered(k) > kMaxCellsPerBox) {
        is_wide_[k] = 1;
        wide_.push_back(static_cast<std::int32_t>(k));
        continue;
      }
      for_each_cell(k, [&](std::int64_t cell) { ++first_[cell + 1]; });
    }
    for (std::int64_t c = 0; c < n_cells; ++c) first_[c + 1] += first_[c];
    entries_.resize(static_cast<std::size_t>(first_[n_cells]));
    std::vector<std::int64_t> next(first_.begin(), first_.end() - 1);
    for (std::size_t k = 0; k < boxes_.size(); ++k)
      if (!is_wide_[k]) for_each_cell(k, [&](std::int64_t cell) { entries_[next[cell]++] = static_cast<std::int32_t>(k); });
  }

  bool periodic_;
  const std::vector<SweptBox<D>>& boxes_;
  Vec<D> origin_;
  std::array<std::int64_t, D> counts_{};
  Vec<D> cell_size_;
  std::vector<std::int64_t> first_;     // per cell, its first entry; one more at the end
  std::vector<std::int32_t> entries_;   // the boxes of each cell
  std::vector<std::int32_t> wide_;      // the boxes not in the grid
  std::vector<char> is_wide_;
};

}  // namespace ballagg
