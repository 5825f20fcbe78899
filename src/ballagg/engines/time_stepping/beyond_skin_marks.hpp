#pragma once
// Marks on the cells of the step's cell list where a move of this step put a sphere beyond
// the near list's half skin, and on the cells next to them (touching spheres are in
// neighbouring cells: a cell is at least a contact distance wide). A sphere in no listed
// near pair, of a cluster still within the half skin, can touch only such a sphere: where
// no cell next to its own is marked, the contact passes skip it (rigid model).
#include <cstdint>
#include <vector>

#include "ballagg/core/parallel.hpp"
#include "ballagg/spatial/grid_geometry.hpp"

namespace ballagg {

template <int D>
class BeyondSkinMarks {
 public:
  void reset(std::int64_t n_cells) {
    mark_.assign(static_cast<std::size_t>(n_cells), 0);
    marked_.clear();
    found_.assign(max_threads(), {});
  }
  // Before a parallel region that calls found_here.
  void fit() { fit_to_team(found_); }
  // The calling thread found a sphere beyond the half skin in `cell`. The spheres of a
  // cluster come one after the other, many in the same cell.
  void found_here(std::int32_t cell) {
    std::vector<std::int32_t>& found = found_[thread_index()];
    if (found.empty() || found.back() != cell) found.push_back(cell);
  }
  // The cells found since the last call are marked, with their neighbours.
  void mark_found(const GridGeometry<D>& grid) {
    for (std::vector<std::int32_t>& found : found_) {
      for (std::int32_t cell : found) {
        if (mark_[cell] & kHoldsBeyond) continue;
        grid.for_each_cell_near(grid.centre(cell), [&](std::int64_t c) { mark_[c] |= kBesideBeyond; });
        mark_[cell] |= kHoldsBeyond;
        marked_.push_back(cell);
      }
      found.clear();
    }
  }
  // Whether a sphere beyond the half skin may be in this cell or the next.
  bool near_beyond(std::int32_t cell) const { return mark_[cell] != 0; }
  void clear(const GridGeometry<D>& grid) {
    for (std::int32_t cell : marked_)
      grid.for_each_cell_near(grid.centre(cell), [&](std::int64_t c) { mark_[c] = 0; });
    marked_.clear();
  }

 private:
  static constexpr char kHoldsBeyond = 1, kBesideBeyond = 2;
  std::vector<char> mark_;                          // per cell
  std::vector<std::int32_t> marked_;                // the cells holding one, to clear them
  std::vector<std::vector<std::int32_t>> found_;    // per thread: cells found, not yet marked
};

}  // namespace ballagg
