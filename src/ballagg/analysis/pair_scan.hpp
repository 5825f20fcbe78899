#pragma once
// One pass over the pairs of sphere centres closer than a cutoff, shared by the contact
// count (4.5) and the pair distribution (4.6). Separations are minimum images in a
// periodic box (true separations for cutoffs below L/2). Each sphere visits all its
// neighbours, so per-sphere results are written by one thread only and every count is an
// integer sum: the results do not depend on the number of threads.
#include <cstdint>
#include <vector>

#include "ballagg/core/parallel.hpp"
#include "ballagg/core/vec.hpp"
#include "ballagg/spatial/box.hpp"
#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {

// Calls visit(thread, i, j, distance) for every ordered pair i != j with
// distance <= cutoff, i in parallel (OpenMP), thread the index of the calling thread.
template <int D, class Visit>
void for_each_pair_within(const Box<D>& box, const std::vector<Vec<D>>& x, double cutoff, Visit&& visit) {
  const int n = static_cast<int>(x.size());
  if (n == 0) return;
  SortedCellList<D> cells(box, cutoff, n);
  cells.build(x);
  const double cutoff2 = cutoff * cutoff;
  // Cell order: neighbours close in memory, and threads take contiguous runs of cells.
  const std::vector<std::int32_t>& order = cells.order();
#pragma omp parallel for schedule(dynamic, 256)
  for (int slot = 0; slot < n; ++slot) {
    const int i = order[slot];
    const int thread = thread_index();
    const Vec<D>& xi = cells.sorted_position(slot);
    cells.for_each_slot_near(xi, [&](std::int32_t other) {
      if (other == slot) return;
      const Vec<D> d = box.separation(cells.sorted_position(other), xi);
      const double r2 = d.squaredNorm();
      if (r2 <= cutoff2) visit(thread, i, order[other], std::sqrt(r2));
    });
  }
}

}  // namespace ballagg
