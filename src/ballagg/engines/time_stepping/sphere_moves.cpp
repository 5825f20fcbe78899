// How the time-stepping engine (ts_engine.hpp) moves spheres: a round's solutions into the
// step's positions (apply), with the cell list, the near list's skin and the sightings
// kept up to date; and at commit, the step's moves into the state.
#include <algorithm>

#include "ballagg/core/parallel.hpp"
#include "ballagg/core/prefetch.hpp"
#include "ballagg/engines/time_stepping/ts_engine.hpp"

namespace ballagg {
namespace {

// Spheres moved by one apply() from which they are moved on several threads (scattered
// reads and writes: worth sharing from about a thousand spheres).
constexpr std::size_t kParallelApply = 1024;

// apply() shares its work among the threads in pieces of at most this many spheres of one
// solution, so that a single solution that moves a giant cluster is shared too.
constexpr std::size_t kApplyPiece = 4096;

}  // namespace

// Moves the spheres of these solutions in positions_ (the state is moved at commit). The
// solutions move disjoint spheres: on several threads, in pieces of kApplyPiece spheres,
// when they are many; the cell list is then updated in solution order.
template <int D>
void TimeSteppingEngine<D>::apply(const State<D>& s, const std::vector<const GroupSolution<D>*>& solutions,
                                  std::vector<int>& moved) {
  const std::size_t n_moved = count_solutions(solutions);
  apply_pieces_.clear();
  std::size_t at = 0;
  for (const GroupSolution<D>* g : solutions)
    for (std::size_t begin = 0; begin < g->spheres.size(); begin += kApplyPiece) {
      const std::size_t end = std::min(g->spheres.size(), begin + kApplyPiece);
      apply_pieces_.push_back({g, begin, end, at, 0});
      at += end - begin;
    }
  // The moved list and the spheres to bin again are filled by the pieces, each in its own range.
  const std::size_t first_moved = moved.size();
  moved.resize(first_moved + n_moved);
  to_rebin_.resize(n_moved);
  if (move_pieces(s, moved, first_moved)) near_list_complete_ = false;
  beyond_skin_.mark_found(cells_.list().sorted().grid());
  // In the order of the spheres in the solutions, as the pieces come.
  for (const ApplyPiece& piece : apply_pieces_)
    for (std::size_t r = piece.at; r < piece.at + piece.n_rebin; ++r) cells_.move_in_list(to_rebin_[r]);
  cells_.rebin_if_many_moved();
}

// The solutions' counts, and the old links of the per-sphere models with their new
// multipliers. Returns how many spheres they move.
template <int D>
std::size_t TimeSteppingEngine<D>::count_solutions(const std::vector<const GroupSolution<D>*>& solutions) {
  std::size_t n_moved = 0;
  for (const GroupSolution<D>* g : solutions) {
    ++counters_.minimisations;
    counters_.daha_iterations += g->result.iterations;
    counters_.max_link_stretch = std::max(counters_.max_link_stretch, g->link_stretch);
    if (g->placed_at_contact) ++counters_.placed_at_contact;
    for (const SpherePair& l : g->old_links) links_.add(l.i, l.j, l.lambda);
    n_moved += g->spheres.size();
  }
  return n_moved;
}

// Moves the spheres of apply_pieces_, on the threads when they are many. Returns whether
// one of them went beyond the near list's half skin.
template <int D>
bool TimeSteppingEngine<D>::move_pieces(const State<D>& s, std::vector<int>& moved, std::size_t first_moved) {
  const Box<D>& box = *box_;
  const GridGeometry<D>& grid = cells_.list().sorted().grid();
  const bool mark_beyond = rigid();  // only the rigid model's contact checks read the marks
  const std::size_t n_moved = to_rebin_.size();
  bool beyond_skin = false;
  const std::int64_t n_pieces = static_cast<std::int64_t>(apply_pieces_.size());
  const int chunk = static_cast<int>(std::clamp<std::int64_t>(n_pieces / 64, 1, 64));
  beyond_skin_.fit();
#pragma omp parallel for schedule(dynamic, chunk) reduction(|| : beyond_skin) \
    if (n_pieces > 1 && n_moved >= kParallelApply)
  for (std::int64_t k = 0; k < n_pieces; ++k) {
    ApplyPiece& piece = apply_pieces_[k];
    const GroupSolution<D>& g = *piece.solution;
    for (std::size_t m = piece.begin; m < piece.end; ++m) {
      // The spheres of a solution are scattered over the arrays (a giant's members): their
      // entries are asked for ahead, or each sphere waits for five loads.
      prefetch_entries(g.spheres, m + kPrefetchAhead, positions_, step_shift_, cells_.moves_since_binned(),
                       sightings_.last_passes(), s.spheres.cluster);
      const int i = g.spheres[m];
      positions_[i] = box.wrap(positions_[i] + g.shift[m]);
      step_shift_[i] += g.shift[m];
      sightings_.moved(i);
      if (beyond_half_skin(s, i)) {
        beyond_skin = true;
        if (mark_beyond) beyond_skin_.found_here(grid.cell_index(positions_[i]));
      }
      moved[first_moved + piece.at + (m - piece.begin)] = i;
      if (cells_.moved(i, s.spheres.cluster[i], g.shift[m])) to_rebin_[piece.at + piece.n_rebin++] = i;
    }
  }
  return beyond_skin;
}

// The per-sphere models: each moved sphere is displaced in its cluster.
template <int D>
void TimeSteppingEngine<D>::commit_moves(State<D>& s, std::vector<std::int32_t>& moved_clusters) {
  for (const int i : moved_in_step_) {
    const int c = s.spheres.cluster[i];
    near_.shifted(c, step_shift_[i].norm());
    cells_.cluster_moved(c, cells_.move_since_binned(i), moved_clusters);
    cells_.forget_move(i);
    s.displace_sphere(i, step_shift_[i]);
  }
  std::vector<std::int32_t> clusters;
  for (int i : moved_in_step_) clusters.push_back(s.spheres.cluster[i]);
  sort_unique(clusters);
  for (int c : clusters) s.refresh_extent(c);
}

// The rigid model: a solution moves every sphere of a cluster by one shift, so a moved
// cluster has all its spheres among the moved ones, and one translation moves it. Each is
// taken once, at its first member, in sphere order (the order of State's stamps); the
// largest drift of its spheres since they were binned is found on the threads, as is the
// test for its first member (a scattered read per sphere).
template <int D>
void TimeSteppingEngine<D>::commit_rigid_moves(State<D>& s, std::vector<std::int32_t>& moved_clusters) {
  const std::int64_t n = static_cast<std::int64_t>(moved_in_step_.size());
  std::vector<double> drift(moved_in_step_.size(), -1.0);  // -1: not its cluster's first member
  const std::vector<Vec<D>>& moves = cells_.moves_since_binned();
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
  for (std::int64_t k = 0; k < n; ++k) {
    const int i = moved_in_step_[k];
    const MemberList& members = s.clusters[s.spheres.cluster[i]].members;
    if (members.front() != i) continue;
    double largest = 0.0;
    for_each_prefetched(members, [&](int j) { largest = std::max(largest, moves[j].norm()); }, moves);
    drift[k] = largest;
  }
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
  for (std::int64_t k = 0; k < n; ++k) cells_.forget_move(moved_in_step_[k]);
  for (std::int64_t k = 0; k < n; ++k) {
    if (drift[k] < 0.0) continue;
    const int i = moved_in_step_[k];
    const int c = s.spheres.cluster[i];
    near_.shifted(c, step_shift_[i].norm());
    cells_.cluster_moved(c, drift[k], moved_clusters);
    s.translate(c, step_shift_[i], s.time);
  }
}

#define BALLAGG_TS_MOVES(D)                                                                                         \
  template void TimeSteppingEngine<D>::apply(const State<D>&, const std::vector<const GroupSolution<D>*>&,         \
                                             std::vector<int>&);                                                    \
  template void TimeSteppingEngine<D>::commit_moves(State<D>&, std::vector<std::int32_t>&);                        \
  template void TimeSteppingEngine<D>::commit_rigid_moves(State<D>&, std::vector<std::int32_t>&);
BALLAGG_TS_MOVES(2)
BALLAGG_TS_MOVES(3)
#undef BALLAGG_TS_MOVES

}  // namespace ballagg
