#pragma once
// One pass over the pairs of sphere centres closer than a cutoff, shared by the contact
// count (4.5) and the pair distribution (4.6). Separations are minimum images in a
// periodic box (true separations for cutoffs below L/2). Each unordered pair is visited
// once, through the half stencil of a sorted cell list (cells at least `cutoff` wide), the
// cells shared out between OpenMP threads. Callers accumulate integers only (per-thread
// histograms, atomic counters), so results do not depend on the number of threads.
#include <cstdint>
#include <vector>

#include "ballagg/core/box.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/core/vec.hpp"
#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {

// Below this many centres the pass runs on one thread: waking a team costs more than the
// work (tens of milliseconds on a loaded machine).
inline constexpr int kParallelPairScanMin = 20000;

// Calls visit(thread, i, j, distance) once for every unordered pair i != j with
// distance <= cutoff, thread the index of the calling OpenMP thread.
template <int D, class Visit>
void for_each_pair_within(const Box<D>& box, const std::vector<Vec<D>>& x, double cutoff, Visit&& visit) {
  const int n = static_cast<int>(x.size());
  if (n == 0) return;
  SortedCellList<D> cells(box, cutoff, n);
  cells.build(x);
  const double cutoff2 = cutoff * cutoff;
  const std::vector<std::int32_t>& order = cells.order();
  auto test = [&](int thread, std::int32_t a, std::int32_t b) {
    const Vec<D> d = box.separation(cells.sorted_position(b), cells.sorted_position(a));
    const double r2 = d.squaredNorm();
    if (r2 <= cutoff2) visit(thread, order[a], order[b], std::sqrt(r2));
  };
  if (!cells.cell_pairs_are_distinct()) {
    // A periodic box fewer than 3 cells wide: from each slot, the later slots near it.
#pragma omp parallel for schedule(dynamic, 256) if (n >= kParallelPairScanMin)
    for (int slot = 0; slot < n; ++slot) {
      const int thread = thread_index();
      cells.for_each_slot_near(cells.sorted_position(slot), [&](std::int32_t other) {
        if (other > slot) test(thread, slot, other);
      });
    }
    return;
  }
  constexpr std::int64_t kCellsPerTask = 64;
  const std::int64_t n_cells = cells.n_cells();
#pragma omp parallel for schedule(dynamic, 1) if (n >= kParallelPairScanMin)
  for (std::int64_t first = 0; first < n_cells; first += kCellsPerTask) {
    const int thread = thread_index();
    cells.for_each_cell_pair(first, std::min(first + kCellsPerTask, n_cells), [&](std::int64_t a, std::int64_t b) {
      const std::int32_t a_end = cells.first_slot(a + 1), b_end = cells.first_slot(b + 1);
      for (std::int32_t s = cells.first_slot(a); s < a_end; ++s)
        for (std::int32_t t = a == b ? s + 1 : cells.first_slot(b); t < b_end; ++t) test(thread, s, t);
    });
  }
}

}  // namespace ballagg
