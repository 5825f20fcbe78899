#pragma once
// A SortedCellList whose items can also be moved one at a time between two rebuilds.
//
// The time-stepping engine bins every sphere once a step (a counting sort, O(N)); its
// minimisations and retreats then move a few spheres at a time, some farther than the cell
// slack allows. Rebuilding after each of them would cost O(N) per group, and keeping the
// moved spheres in one list apart would cost every query the length of that list: at large
// N either outweighs the rest of a step. Here a moved item leaves its sorted slot (skipped
// from then on) for a short list of the cell it moved into, so a move costs O(1) plus the
// length of two cell lists, and a query still visits only the cells around its point.
#include <cstdint>
#include <vector>

#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"
#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {

template <int D>
class MovableCellList {
 public:
  MovableCellList(const Box<D>& box, double min_cell_size, int n_items)
      : sorted_(box, min_cell_size, n_items),
        moved_(n_items, 0),
        moved_cell_(n_items, -1),
        next_(n_items, -1),
        head_(sorted_.grid().n_cells(), -1) {}

  double cell_size() const { return sorted_.cell_size(); }

  // Bins every item at x[id]; no item is moved afterwards.
  void build(const std::vector<Vec<D>>& x) {
    clear_moves();
    sorted_.build(x);
  }

  // The sorted list alone: valid while no item has moved (slot order, cell pairs).
  const SortedCellList<D>& sorted() const { return sorted_; }
  std::size_t n_moved() const { return moved_list_.size(); }

  // Item id is now binned at p (a point in the box; one a round-off outside is clamped).
  void move(std::int32_t id, const Vec<D>& p) {
    const std::int32_t cell = sorted_.grid().cell_index(p);
    if (moved_[id]) {
      if (moved_cell_[id] == cell) return;
      unlink(id);
    } else {
      moved_[id] = 1;
      moved_list_.push_back(id);
    }
    moved_cell_[id] = cell;
    next_[id] = head_[cell];
    head_[cell] = id;
  }

  // Calls f(id) for every item binned in the cells adjacent to p (each cell once).
  template <class F>
  void for_each_near(const Vec<D>& p, F&& f) const {
    sorted_.grid().for_each_cell_near(p, [&](std::int64_t c) { for_each_in_cell(c, f); });
  }

  // Calls f(id) for every item binned in a cell that holds points within radius of p.
  template <class F>
  void for_each_within(const Vec<D>& p, double radius, F&& f) const {
    sorted_.grid().for_each_cell_within(p, radius, [&](std::int64_t c) { for_each_in_cell(c, f); });
  }

  // Calls f(id) for every item binned in a cell that may hold points within radius of the
  // segment from a to a + d.
  template <class F>
  void for_each_near_segment(const Vec<D>& a, const Vec<D>& d, double radius, F&& f) const {
    sorted_.grid().for_each_cell_near_segment(a, d, radius, [&](std::int64_t c) { for_each_in_cell(c, f); });
  }

 private:
  template <class F>
  void for_each_in_cell(std::int64_t c, F& f) const {
    if (moved_list_.empty()) {
      sorted_.for_each_in_cell(c, f);
      return;
    }
    sorted_.for_each_in_cell(c, [&](std::int32_t id) {
      if (!moved_[id]) f(id);
    });
    for (std::int32_t id = head_[c]; id >= 0; id = next_[id]) f(id);
  }

  void unlink(std::int32_t id) {
    std::int32_t* link = &head_[moved_cell_[id]];
    while (*link != id) link = &next_[*link];
    *link = next_[id];
  }

  void clear_moves() {
    for (std::int32_t id : moved_list_) {
      head_[moved_cell_[id]] = -1;
      moved_[id] = 0;
    }
    moved_list_.clear();
  }

  SortedCellList<D> sorted_;
  std::vector<char> moved_;               // per item: re-binned by move() since the build
  std::vector<std::int32_t> moved_cell_;  // per moved item: the cell it is binned in
  std::vector<std::int32_t> next_;        // per moved item: the next moved item of that cell
  std::vector<std::int32_t> head_;        // per cell: its first moved item, or -1
  std::vector<std::int32_t> moved_list_;  // the moved items (to clear them)
};

}  // namespace ballagg
