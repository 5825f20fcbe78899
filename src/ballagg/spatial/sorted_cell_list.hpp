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

#include "ballagg/core/box.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/core/vec.hpp"
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
  // The slots of a cell hold its items in increasing id, whatever the number of threads.
  void build(const std::vector<Vec<D>>& x) {
    const int n = static_cast<int>(x.size());
    cell_.resize(n);
    order_.resize(n);
    sorted_.resize(n);
    if (n < kParallelLoopMin || max_threads() == 1) {
      build_serial(x);
      return;
    }
    // A counting sort shared among the threads: each counts, then scatters, a block of
    // the items (the cell index, a division per axis, and the scatter, with its random
    // writes, are nearly all of a build, and both divide among threads). A
    // cell's slots hold the items of the first block, then of the second, and so on: in
    // increasing id, as the serial sort leaves them.
    const std::int64_t n_cells = grid_.n_cells();
#pragma omp parallel
    {
      const int threads = team_size(), t = thread_index();
#pragma omp single
      {
        counts_.resize(threads);
        block_totals_.assign(threads, 0);
      }  // (the implicit barrier: the arrays exist for every thread from here)
      std::vector<std::int32_t>& mine = counts_[t];
      mine.assign(n_cells, 0);
      const int first = static_cast<int>(static_cast<std::int64_t>(n) * t / threads);
      const int last = static_cast<int>(static_cast<std::int64_t>(n) * (t + 1) / threads);
      for (int i = first; i < last; ++i) ++mine[cell_[i] = grid_.cell_index(x[i])];
#pragma omp barrier
      // Cells are shared out in blocks too: each block's total, then its slots.
      const std::int64_t c0 = n_cells * t / threads, c1 = n_cells * (t + 1) / threads;
      std::int32_t total = 0;
      for (std::int64_t c = c0; c < c1; ++c)
        for (int u = 0; u < threads; ++u) total += counts_[u][c];
      block_totals_[t] = total;
#pragma omp barrier
      std::int32_t slot = 0;
      for (int u = 0; u < t; ++u) slot += block_totals_[u];
      for (std::int64_t c = c0; c < c1; ++c) {
        start_[c] = slot;
        for (int u = 0; u < threads; ++u) {
          const std::int32_t count = counts_[u][c];
          counts_[u][c] = slot;  // from here: the next free slot of block u in cell c
          slot += count;
        }
      }
      if (t == threads - 1) start_[n_cells] = n;
#pragma omp barrier
      for (int i = first; i < last; ++i) {
        const std::int32_t at = mine[cell_[i]]++;
        order_[at] = i;
        sorted_[at] = x[i];
      }
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
  void build_serial(const std::vector<Vec<D>>& x) {
    const int n = static_cast<int>(x.size());
    for (int i = 0; i < n; ++i) cell_[i] = grid_.cell_index(x[i]);
    std::fill(start_.begin(), start_.end(), 0);
    for (int i = 0; i < n; ++i) ++start_[cell_[i] + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    std::vector<std::int32_t> fill(start_.begin(), start_.end() - 1);
    for (int i = 0; i < n; ++i) {
      const std::int32_t slot = fill[cell_[i]]++;
      order_[slot] = i;
      sorted_[slot] = x[i];
    }
  }

  GridGeometry<D> grid_;
  std::vector<std::int32_t> start_;  // per cell: first slot in order_ (and one past the end)
  std::vector<std::int32_t> cell_;   // per item
  std::vector<std::int32_t> order_;  // item ids sorted by cell
  std::vector<Vec<D>> sorted_;       // their positions, in the same order
  std::vector<std::vector<std::int32_t>> counts_;  // per thread of a build: per cell, its items, then its next slot
  std::vector<std::int32_t> block_totals_;         // per thread of a build: the items of its block of cells
};

}  // namespace ballagg
