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

#include "ballagg/core/vec.hpp"
#include "ballagg/spatial/box.hpp"

namespace ballagg {

template <int D>
class SortedCellList {
 public:
  // Cells at least `min_cell_size` wide, and not many more cells than items (a dilute
  // system in a huge box gets larger cells, which stay correct).
  SortedCellList(const Box<D>& box, double min_cell_size, int n_items) : box_(box) {
    const double by_size = std::floor(box.length / min_cell_size);
    const double by_count = std::ceil(std::pow(2.0 * std::max(n_items, 1), 1.0 / D));
    per_side_ = static_cast<int>(std::clamp(std::min(by_size, by_count), 1.0, 1e6));
    cell_size_ = box.length / per_side_;
    std::int64_t cells = 1;
    for (int a = 0; a < D; ++a) cells *= per_side_;
    start_.assign(cells + 1, 0);
  }

  double cell_size() const { return cell_size_; }
  // Item ids in cell order ("slots"): iterating in this order visits neighbours close in
  // memory. sorted_position(slot) is the binned position of the item in that slot.
  const std::vector<std::int32_t>& order() const { return order_; }
  const Vec<D>& sorted_position(int slot) const { return sorted_[slot]; }

  // Bins every item at x[id] (points in the box; those a round-off outside are clamped).
  void build(const std::vector<Vec<D>>& x) {
    const int n = static_cast<int>(x.size());
    cell_.resize(n);
    std::fill(start_.begin(), start_.end(), 0);
    for (int i = 0; i < n; ++i) {
      cell_[i] = cell_index(x[i]);
      ++start_[cell_[i] + 1];
    }
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
    std::array<std::array<int, 3>, D> coords;
    std::array<int, D> counts;
    for (int a = 0; a < D; ++a) counts[a] = neighbour_coords(coordinate(p[a]), coords[a]);
    std::array<int, D> k{};
    while (true) {
      std::int64_t cell = 0;
      for (int a = D - 1; a >= 0; --a) cell = cell * per_side_ + coords[a][k[a]];
      for (std::int32_t s = start_[cell]; s < start_[cell + 1]; ++s) f(s);
      int a = 0;
      while (a < D && ++k[a] == counts[a]) k[a++] = 0;
      if (a == D) break;
    }
  }

 private:
  int coordinate(double x) const { return std::clamp(static_cast<int>(x / cell_size_), 0, per_side_ - 1); }
  std::int32_t cell_index(const Vec<D>& p) const {
    std::int64_t cell = 0;
    for (int a = D - 1; a >= 0; --a) cell = cell * per_side_ + coordinate(p[a]);
    return static_cast<std::int32_t>(cell);
  }
  int neighbour_coords(int c, std::array<int, 3>& out) const {
    int n = 0;
    for (int d = -1; d <= 1; ++d) {
      int x = c + d;
      if (box_.periodic()) x = (x + per_side_) % per_side_;
      else if (x < 0 || x >= per_side_) continue;
      if (std::find(out.begin(), out.begin() + n, x) == out.begin() + n) out[n++] = x;
    }
    return n;
  }

  Box<D> box_;
  int per_side_ = 1;
  double cell_size_ = 1.0;
  std::vector<std::int32_t> start_;  // per cell: first slot in order_ (and one past the end)
  std::vector<std::int32_t> cell_;   // per item
  std::vector<std::int32_t> order_;  // item ids sorted by cell
  std::vector<Vec<D>> sorted_;       // their positions, in the same order
};

}  // namespace ballagg
