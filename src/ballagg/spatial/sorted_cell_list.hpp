#pragma once
// A cell list rebuilt from scratch by a counting sort: items ordered by cell, each cell a
// contiguous range. Building costs two passes over the items, and a query reads
// contiguous memory. This suits the time-stepping engine, where every sphere moves every
// step, better than the linked cells of CellGrid (which suit event-driven updates of one
// item at a time).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "ballagg/core/parallel.hpp"
#include "ballagg/core/vec.hpp"
#include "ballagg/spatial/box.hpp"
#include "ballagg/spatial/grid_geometry.hpp"

namespace ballagg {

template <int D>
class SortedCellList {
 public:
  // Cells at least `min_cell_size` wide, and not many more cells than items (a dilute
  // system in a huge box gets larger cells, which stay correct).
  SortedCellList(const Box<D>& box, double min_cell_size, int n_items) : grid_(box, min_cell_size, n_items) {
    start_.assign(grid_.n_cells() + 1, 0);
  }

  double cell_size() const { return grid_.cell_size(); }
  const GridGeometry<D>& grid() const { return grid_; }
  // Item ids in cell order ("slots"): iterating in this order visits neighbours close in
  // memory. sorted_position(slot) is the binned position of the item in that slot.
  const std::vector<std::int32_t>& order() const { return order_; }
  const Vec<D>& sorted_position(int slot) const { return sorted_[slot]; }

  // Bins every item at x[id] (points in the box; those a round-off outside are clamped).
  void build(const std::vector<Vec<D>>& x) {
    const int n = static_cast<int>(x.size());
    cell_.resize(n);
    // The cell of each item on every thread (the divisions are most of a build); the
    // counts and the scatter below stay in item order, so the slots do not depend on the
    // number of threads.
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
    for (int i = 0; i < n; ++i) cell_[i] = grid_.cell_index(x[i]);
    std::fill(start_.begin(), start_.end(), 0);
    for (int i = 0; i < n; ++i) ++start_[cell_[i] + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    order_.resize(n);
    sorted_.resize(n);
    std::vector<std::int32_t> fill(start_.begin(), start_.end() - 1);
    for (int i = 0; i < n; ++i) {
      const std::int32_t slot = fill[cell_[i]]++;
      order_[slot] = i;
      sorted_[slot] = x[i];
    }
  }

  // Calls f(id) for every item binned in the cells adjacent to p (each cell once).
  template <class F>
  void for_each_near(const Vec<D>& p, F&& f) const {
    for_each_slot_near(p, [&](std::int32_t slot) { f(order_[slot]); });
  }

  // Calls f(slot) for every slot of the cells adjacent to p (each cell once).
  template <class F>
  void for_each_slot_near(const Vec<D>& p, F&& f) const {
    grid_.for_each_cell_near(p, [&](std::int64_t cell) {
      for (std::int32_t s = start_[cell]; s < start_[cell + 1]; ++s) f(s);
    });
  }

  // The half stencil: every unordered pair of adjacent non-empty cells once, and every
  // non-empty cell with itself. Not available (false) when a periodic grid has fewer than
  // 3 cells a side (neighbours would repeat); use for_each_slot_near then.
  bool cell_pairs_are_distinct() const { return !grid_.box().periodic() || grid_.per_side() >= 3; }
  std::int64_t n_cells() const { return grid_.n_cells(); }
  // The slots of cell c are first_slot(c) to first_slot(c + 1) - 1.
  std::int32_t first_slot(std::int64_t c) const { return start_[c]; }
  // Cells `first` to `last` - 1 and their forward neighbours; f(cell, other).
  template <class F>
  void for_each_cell_pair(std::int64_t first, std::int64_t last, F&& f) const {
    grid_.for_each_cell_pair(first, last, [&](std::int64_t a, std::int64_t b) {
      if (start_[a] != start_[a + 1] && start_[b] != start_[b + 1]) f(a, b);
    });
  }

  // Calls f(id) for every item binned in cell c.
  template <class F>
  void for_each_in_cell(std::int64_t c, F&& f) const {
    for (std::int32_t s = start_[c]; s < start_[c + 1]; ++s) f(order_[s]);
  }

  // Calls f(id) for every item binned in a cell that holds points within radius of p.
  template <class F>
  void for_each_within(const Vec<D>& p, double radius, F&& f) const {
    grid_.for_each_cell_within(p, radius, [&](std::int64_t cell) {
      for (std::int32_t s = start_[cell]; s < start_[cell + 1]; ++s) f(order_[s]);
    });
  }

  // Calls f(id) for every item binned in a cell that may hold points within radius of
  // the segment from a to a + d.
  template <class F>
  void for_each_near_segment(const Vec<D>& a, const Vec<D>& d, double radius, F&& f) const {
    grid_.for_each_cell_near_segment(a, d, radius, [&](std::int64_t cell) {
      for (std::int32_t s = start_[cell]; s < start_[cell + 1]; ++s) f(order_[s]);
    });
  }

 private:
  GridGeometry<D> grid_;
  std::vector<std::int32_t> start_;  // per cell: first slot in order_ (and one past the end)
  std::vector<std::int32_t> cell_;   // per item
  std::vector<std::int32_t> order_;  // item ids sorted by cell
  std::vector<Vec<D>> sorted_;       // their positions, in the same order
};

}  // namespace ballagg
