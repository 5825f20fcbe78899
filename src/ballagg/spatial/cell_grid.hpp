#pragma once
// A uniform grid of cells over the box, each holding a doubly linked list of item ids, so
// that inserting, moving and removing an item costs O(1) and a query visits only the 3^D
// cells around a point. Cells are at least `min_cell_size` wide, so every item within
// that distance of the query point is visited. Each node keeps the position the item was
// binned at next to its link, so a query can reject far items without touching any other
// memory (the traversal is bound by memory latency, not arithmetic).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "ballagg/core/box.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/vec.hpp"
#include "ballagg/spatial/grid_geometry.hpp"

namespace ballagg {

template <int D>
class CellGrid {
 public:
  // The number of cells is also capped near `max_cells_per_item * n_items`, so a dilute
  // system in a huge box does not allocate a huge, empty grid (larger cells stay correct).
  CellGrid(const Box<D>& box, double min_cell_size, int n_items, double max_cells_per_item = 2.0)
      : CellGrid(GridGeometry<D>(box, min_cell_size, n_items, max_cells_per_item), n_items) {}
  CellGrid(const GridGeometry<D>& grid, int n_items) : box_(grid.box()), grid_(grid), per_side_(grid_.per_side()) {
    head_.assign(grid_.n_cells(), -1);
    cell_tag_.assign(grid_.n_cells(), kMixed);
    node_.assign(n_items, Node{});
  }

  int per_side() const { return per_side_; }
  double cell_size() const { return grid_.cell_size(); }

  // p must lie in the box (folded into it when periodic); points on the faces are clamped.
  void insert(int id, const Vec<D>& p) {
    node_[id].position = p;
    link(id, cell_index(p));
  }
  // Every item carries a tag >= 0 (0 unless set) that for_each_near_image can skip on:
  // the engine tags spheres with their cluster, so that a big cluster's own spheres, most
  // of what a scan around its members meets, are passed over without reading anything
  // else, and a cell holding nothing but them is not even walked.
  void set_tag(int id, std::int32_t tag) {
    node_[id].tag = tag;
    if (node_[id].cell >= 0) retag_cell(node_[id].cell);
  }

  // Where item id was binned.
  const Vec<D>& binned(int id) const { return node_[id].position; }

  void move(int id, const Vec<D>& p) {
    node_[id].position = p;
    const std::int32_t c = cell_index(p);
    if (c == node_[id].cell) return;
    unlink(id);
    link(id, c);
  }

  // Takes item id out of its cell: no query visits it until it is inserted again.
  void remove(int id) {
    unlink(id);
    node_[id].cell = -1;
  }
  // Drops the last item, removed before: ids stay dense when an item leaves for good.
  void pop_back() { node_.pop_back(); }

  // Calls f(id, binned position) for every item in the cells adjacent to p (each cell
  // visited once).
  template <class F>
  void for_each_near(const Vec<D>& p, F&& f) const {
    grid_.for_each_cell_near(p, [&](std::int64_t cell) {
      for (std::int32_t id = head_[cell]; id >= 0; id = node_[id].next) f(id, node_[id].position);
    });
  }

  // As for_each_near, skipping the items tagged skip_tag, but f(id, image) gets the image
  // of the binned position next to p's cell: the nearest image whenever it lies within one
  // cell of p. Comparing it with p needs no minimum-image rounding (the hot path of list
  // rebuilds): with three or more cells a side, each neighbour cell is one image of a box
  // cell, shifted by -L, 0 or L.
  template <class F>
  void for_each_near_image(const Vec<D>& p, std::int32_t skip_tag, F&& f) const {
    if (box_.periodic() && per_side_ < 3) {
      for_each_near(p, [&](int id, const Vec<D>& x) {
        if (node_[id].tag != skip_tag) f(id, Vec<D>(p - box_.separation(p, x)));
      });
      return;
    }
    std::array<std::array<std::int64_t, 3>, D> stride;  // cell index term of each neighbour
    std::array<std::array<double, 3>, D> shift;
    std::array<int, D> counts;
    std::int64_t step = 1;
    for (int a = 0; a < D; ++a) {
      const int c = grid_.coordinate(p[a]);
      counts[a] = 0;
      for (int d = -1; d <= 1; ++d) {
        int x = c + d;
        double offset = 0.0;
        if (x < 0 || x >= per_side_) {
          if (!box_.periodic()) continue;
          offset = x < 0 ? -box_.length : box_.length;
          x = x < 0 ? x + per_side_ : x - per_side_;
        }
        stride[a][counts[a]] = x * step;
        shift[a][counts[a]++] = offset;
      }
      step *= per_side_;
    }
    std::array<int, D> k{};
    while (true) {
      std::int64_t cell = 0;
      for (int a = 0; a < D; ++a) cell += stride[a][k[a]];
      if (cell_tag_[cell] != skip_tag) {
        Vec<D> offset;
        for (int a = 0; a < D; ++a) offset[a] = shift[a][k[a]];
        for (std::int32_t id = head_[cell]; id >= 0; id = node_[id].next)
          if (node_[id].tag != skip_tag) f(id, Vec<D>(node_[id].position + offset));
      }
      int a = 0;
      while (a < D && ++k[a] == counts[a]) k[a++] = 0;
      if (a == D) break;
    }
  }

  // Checkpoints: every item's binned position and tag, and the order of each cell's list,
  // so that a grid restored into one built with the same box, cell size and item count
  // visits items in the same order as the saved one.
  void save(ByteWriter& w) const {
    std::vector<std::int32_t> sequence;  // the cells' lists one after the other
    sequence.reserve(node_.size());
    for (std::size_t c = 0; c < head_.size(); ++c)
      for (std::int32_t id = head_[c]; id >= 0; id = node_[id].next) sequence.push_back(id);
    w.put_vector(sequence);
    for (const Node& n : node_) {
      w.put(n.position);
      w.put(n.tag);
    }
  }
  void restore(ByteReader& r) {
    const std::vector<std::int32_t> sequence = r.get_vector<std::int32_t>("cell lists", node_.size());
    std::vector<char> seen(node_.size(), 0);
    for (std::int32_t id : sequence) {
      if (id < 0 || static_cast<std::size_t>(id) >= node_.size() || seen[id]) r.fail("cell lists name an item twice or none");
      seen[id] = 1;
    }
    for (Node& n : node_) {
      n = Node{};
      n.position = r.get<Vec<D>>("binned position");
      n.tag = r.get<std::int32_t>("cell tag");
      for (int a = 0; a < D; ++a)
        if (!(n.position[a] >= 0.0 && n.position[a] <= box_.length)) r.fail("binned position outside the box");
    }
    std::fill(head_.begin(), head_.end(), -1);
    std::fill(cell_tag_.begin(), cell_tag_.end(), kMixed);
    // link() puts an item at the head of its cell's list: the saved order, backwards.
    for (auto k = sequence.rbegin(); k != sequence.rend(); ++k) link(*k, cell_index(node_[*k].position));
  }

 private:
  std::int32_t cell_index(const Vec<D>& p) const { return grid_.cell_index(p); }
  void link(int id, std::int32_t c) {
    Node& n = node_[id];
    cell_tag_[c] = head_[c] < 0 || cell_tag_[c] == n.tag ? n.tag : kMixed;
    n.cell = c;
    n.prev = -1;
    n.next = head_[c];
    if (head_[c] >= 0) node_[head_[c]].prev = id;
    head_[c] = id;
  }
  void unlink(int id) {
    const Node& n = node_[id];
    if (n.prev >= 0) node_[n.prev].next = n.next; else head_[n.cell] = n.next;
    if (n.next >= 0) node_[n.next].prev = n.prev;
    if (cell_tag_[n.cell] == kMixed) retag_cell(n.cell);
  }
  // The tag all items of cell c share, or kMixed (cells hold a few items: a short walk).
  void retag_cell(std::int32_t c) {
    std::int32_t tag = head_[c] >= 0 ? node_[head_[c]].tag : kMixed;
    for (std::int32_t id = head_[c]; id >= 0 && tag != kMixed; id = node_[id].next)
      if (node_[id].tag != tag) tag = kMixed;
    cell_tag_[c] = tag;
  }

  Box<D> box_;
  GridGeometry<D> grid_;
  int per_side_;  // copied from grid_: read in the hot loop of for_each_near_image
  struct Node {
    Vec<D> position = Vec<D>::Zero();
    std::int32_t next = -1, prev = -1, cell = -1;
    std::int32_t tag = 0;  // fills the padding of the node in 2D and 3D
  };
  static constexpr std::int32_t kMixed = -1;
  std::vector<std::int32_t> head_;      // per cell: first item, or -1
  std::vector<std::int32_t> cell_tag_;  // per cell: the tag of all its items, or kMixed
  std::vector<Node> node_;          // per item
};

}  // namespace ballagg
