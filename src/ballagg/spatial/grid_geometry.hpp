#pragma once
// The geometry shared by the cell structures (CellGrid, SortedCellList): a uniform grid of
// per_side^D cubic cells over the box, at least `min_cell_size` wide, numbered x-fastest,
// and the walk over the 3^D cells around a point (wrapped across periodic faces, each
// distinct cell once).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

template <int D>
class GridGeometry {
 public:
  // The number of cells is also capped near `max_cells_per_item * n_items`, so a dilute
  // system in a huge box does not allocate a huge, empty grid (larger cells stay correct).
  GridGeometry(const Box<D>& box, double min_cell_size, int n_items, double max_cells_per_item = 2.0) : box_(box) {
    // The input ranges (config/value_ranges.hpp) keep both finite; a NaN here would make
    // the cell count undefined.
    if (!(std::isfinite(box.length) && box.length > 0.0 && min_cell_size > 0.0))
      throw std::logic_error("cell grid: the box length and the cell size must be positive numbers");
    const double by_size = std::floor(box.length / min_cell_size);
    const double by_count = std::ceil(std::pow(max_cells_per_item * std::max(n_items, 1), 1.0 / D));
    per_side_ = static_cast<int>(std::clamp(std::min(by_size, by_count), 1.0, 1e6));
    cell_size_ = box.length / per_side_;
  }
  // A grid of exactly `per_side.value` cells a side (>= 1): one rebuilt as it was saved.
  struct CellsPerSide {
    int value;
  };
  GridGeometry(const Box<D>& box, CellsPerSide per_side)
      : box_(box), per_side_(per_side.value), cell_size_(box.length / per_side.value) {
    if (per_side.value < 1) throw std::logic_error("cell grid: at least one cell a side");
  }

  const Box<D>& box() const { return box_; }
  int per_side() const { return per_side_; }
  double cell_size() const { return cell_size_; }
  std::int64_t n_cells() const {
    std::int64_t cells = 1;
    for (int a = 0; a < D; ++a) cells *= per_side_;
    return cells;
  }

  // Truncation equals floor for x >= 0; points a round-off outside the box are clamped.
  int coordinate(double x) const { return std::clamp(static_cast<int>(x / cell_size_), 0, per_side_ - 1); }
  std::int32_t cell_index(const Vec<D>& p) const {
    std::int64_t cell = 0;
    for (int a = D - 1; a >= 0; --a) cell = cell * per_side_ + coordinate(p[a]);
    return static_cast<std::int32_t>(cell);
  }

  // The centre of a cell (its index as cell_index numbers it: x fastest).
  Vec<D> centre(std::int64_t cell) const {
    Vec<D> c;
    for (int a = 0; a < D; ++a, cell /= per_side_) c[a] = (static_cast<double>(cell % per_side_) + 0.5) * cell_size_;
    return c;
  }

  // Calls f(cell index) for each distinct cell adjacent to the cell of p.
  template <class F>
  void for_each_cell_near(const Vec<D>& p, F&& f) const {
    std::array<std::array<int, 3>, D> coords;
    std::array<int, D> counts;
    for (int a = 0; a < D; ++a) counts[a] = neighbour_coords(coordinate(p[a]), coords[a]);
    std::array<int, D> k{};
    while (true) {
      std::int64_t cell = 0;
      for (int a = D - 1; a >= 0; --a) cell = cell * per_side_ + coords[a][k[a]];
      f(cell);
      int a = 0;
      while (a < D && ++k[a] == counts[a]) k[a++] = 0;
      if (a == D) break;
    }
  }

  // Calls f(cell index) for each distinct cell that may hold points within `radius` of p:
  // the capsule of a segment of length zero (the cells of the ball's bounding box whose
  // centre is near enough, without allocating; the guards of every minimisation problem
  // are searched so, around each sphere of its queried clusters).
  template <class F>
  void for_each_cell_within(const Vec<D>& p, double radius, F&& f) const {
    for_each_cell_near_segment(p, Vec<D>::Zero(), radius, f);
  }

  // Calls f(cell index) for each distinct cell that may hold points within `radius` of the
  // segment from a to a + d (a capsule; a need not lie in the box: periodic coordinates
  // are wrapped, those beyond a wall clamped). Cells are taken from the capsule's bounding
  // box and kept when their centre lies within radius + half a cell diagonal of the
  // segment, so a long oblique segment costs the cells along it, not the square around it.
  // Not filtered: cells on a wall (they also hold the points clamped from beyond it), and
  // every cell when the capsule wraps all the way round a periodic axis.
  template <class F>
  void for_each_cell_near_segment(const Vec<D>& a, const Vec<D>& d, double radius, F&& f) const {
    std::array<int, D> lo, hi;
    bool filter = true;
    for (int k = 0; k < D; ++k) {
      const double low = std::min(a[k], a[k] + d[k]) - radius, high = std::max(a[k], a[k] + d[k]) + radius;
      lo[k] = static_cast<int>(std::floor(low / cell_size_));
      hi[k] = static_cast<int>(std::floor(high / cell_size_));
      if (box_.periodic()) {
        if (hi[k] - lo[k] + 1 >= per_side_) lo[k] = 0, hi[k] = per_side_ - 1, filter = false;  // every cell once
      } else {
        lo[k] = std::max(lo[k], 0);
        hi[k] = std::min(hi[k], per_side_ - 1);
        if (lo[k] > hi[k]) return;
      }
    }
    const double keep = radius + 0.5 * std::sqrt(static_cast<double>(D)) * cell_size_;
    std::array<int, D> x = lo;
    while (true) {
      Vec<D> centre;
      for (int k = 0; k < D; ++k) centre[k] = (x[k] + 0.5) * cell_size_;
      bool on_wall = false;
      for (int k = 0; k < D; ++k) on_wall = on_wall || (!box_.periodic() && (x[k] == 0 || x[k] == per_side_ - 1));
      if (!filter || on_wall || squared_distance_to_segment<D>(centre, a, d) <= keep * keep) {
        std::int64_t cell = 0;
        for (int k = D - 1; k >= 0; --k) cell = cell * per_side_ + ((x[k] % per_side_) + per_side_) % per_side_;
        f(cell);
      }
      int k = 0;
      while (k < D && ++x[k] > hi[k]) x[k] = lo[k], ++k;
      if (k == D) break;
    }
  }

  // Calls f(cell, other) once for every unordered pair of distinct adjacent cells and
  // f(cell, cell) for every cell: the half stencil, for visiting each pair of items once.
  // Needs at least 3 cells a side when periodic (otherwise neighbours repeat).
  // Cells `first` to `last` - 1 only (to share the work between threads).
  template <class F>
  void for_each_cell_pair(std::int64_t first, std::int64_t last, F&& f) const {
    std::array<int, D> c;
    for (std::int64_t rest = first, a = 0; a < D; ++a, rest /= per_side_) c[a] = static_cast<int>(rest % per_side_);
    for (std::int64_t index = first; index < last; ++index) {
      // Offsets in {-1, 0, 1}^D, lexicographically after zero: half of the 3^D - 1.
      std::array<int, D> o;
      o.fill(-1);
      while (true) {
        bool after_zero = false;
        for (int a = D - 1; a >= 0; --a)
          if (o[a] != 0) { after_zero = o[a] > 0; break; }
        bool all_zero = true;
        for (int a = 0; a < D; ++a) all_zero = all_zero && o[a] == 0;
        if (all_zero) {
          f(index, index);
        } else if (after_zero) {
          std::int64_t other = 0;
          bool inside = true;
          for (int a = D - 1; a >= 0; --a) {
            int x = c[a] + o[a];
            if (x < 0 || x >= per_side_) {
              if (!box_.periodic()) { inside = false; break; }
              x = (x + per_side_) % per_side_;
            }
            other = other * per_side_ + x;
          }
          if (inside) f(index, other);
        }
        int a = 0;
        while (a < D && ++o[a] == 2) o[a++] = -1;
        if (a == D) break;
      }
      int a = 0;
      while (a < D && ++c[a] == per_side_) c[a++] = 0;
    }
  }

 private:
  // The distinct cell coordinates next to c along one axis (wrapped if periodic).
  int neighbour_coords(int c, std::array<int, 3>& out) const {
    int n = 0;
    for (int d = -1; d <= 1; ++d) {
      int x = c + d;
      if (box_.periodic()) {
        x = (x + per_side_) % per_side_;
      } else if (x < 0 || x >= per_side_) {
        continue;
      }
      if (std::find(out.begin(), out.begin() + n, x) == out.begin() + n) out[n++] = x;
    }
    return n;
  }

  Box<D> box_;
  int per_side_ = 1;
  double cell_size_ = 1.0;
};

}  // namespace ballagg
