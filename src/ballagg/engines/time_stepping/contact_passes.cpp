// The contact passes of the time-stepping engine (ts_engine.hpp): after a round has moved
// spheres, which of them touch or overlap another sphere. They give (3.2)'s new pairs
// (new_overlaps) and the clusters a settling retreat runs into (settle.cpp), and record
// what they see for the step's residual overlap (OverlapSightings).
#include <algorithm>
#include <cmath>

#include "ballagg/core/parallel.hpp"
#include "ballagg/engines/time_stepping/ts_engine.hpp"

namespace ballagg {

// Calls f(i, j, d, sigma) for every pair of a sphere of `spheres` (sorted, each once) and
// another sphere with phi >= 0 (d <= sigma), spheres of one cluster excepted in the rigid
// model (their distances never change). With several threads, calls for different i
// overlap.
template <int D>
template <class F>
void TimeSteppingEngine<D>::for_each_contact(const State<D>& s, const std::vector<int>& spheres, F&& f) const {
  const bool same_cluster_fixed = rigid();
  // Most spheres a cell query meets are farther than the largest contact distance, 2 R_max:
  // they are passed over on their squared distance, before a radius is read (a scattered
  // read) and a square root taken; the same pairs reach f.
  const double far2 = beyond_squared(2.0 * s.max_radius());
  const MovableCellList<D>& cells = cells_.list();
  const std::int64_t n = static_cast<std::int64_t>(spheres.size());
#pragma omp parallel for schedule(dynamic, 256) if (n >= kParallelLoopMin)
  for (std::int64_t k = 0; k < n; ++k) {
    const int i = spheres[k];
    if (needs_no_contact_query(s, i)) continue;
    const int ci = s.spheres.cluster[i];
    auto visit = [&](int j) {
      if (j == i || (same_cluster_fixed && s.spheres.cluster[j] == ci)) return;
      const double d2 = s.box.separation(positions_[i], positions_[j]).squaredNorm();
      if (d2 > far2) return;
      const double sigma = s.spheres.radius[i] + s.spheres.radius[j];
      const double d = std::sqrt(d2);  // what norm() gives
      if (d <= sigma) f(i, j, d, sigma);
    };
    cells.for_each_near(positions_[i], visit);
  }
}

// Whether the contact passes can skip sphere i (rigid model: only other clusters count).
// A sphere in no listed near pair is farther than its contact distance from every sphere
// of another cluster, as long as both clusters are within the near list's half skin of
// where their pairs were listed (NearPairs::listed). So it is skipped when its cluster is,
// and no sphere moved beyond the half skin in this step is in a cell next to its own
// (BeyondSkinMarks). A small cluster that hits a large one moves it by a tiny shift: each
// of the large cluster's spheres is then a lookup instead of a cell query.
template <int D>
bool TimeSteppingEngine<D>::needs_no_contact_query(const State<D>& s, int i) const {
  if (!rigid() || near_.listed(i)) return false;
  if (near_list_complete_) return true;
  return !beyond_skin_.near_beyond(cells_.list().sorted().grid().cell_index(positions_[i])) &&
         !beyond_half_skin(s, i);
}

// A pass over the spheres moved since the previous one (`moved`, sorted, each once: every
// sphere apply() moved since), calling f as for_each_contact does, and keeping what it sees
// for the residual overlap: the overlaps that could raise max_residual_overlap.
template <int D>
template <class F>
void TimeSteppingEngine<D>::contact_pass(const State<D>& s, const std::vector<int>& moved, F&& f) {
  const std::int32_t pass = sightings_.begin_pass();
  const double largest_so_far = counters_.max_residual_overlap;
  for_each_contact(s, moved, [&](int i, int j, double d, double sigma) {
    const double overlap = 1.0 - d / sigma;
    if (overlap > largest_so_far) sightings_.seen(i, j, pass, overlap);
    f(i, j, d, sigma);
  });
}

// (3.2): the pairs brought to contact (phi >= 0) by this round, sorted. A pair of S, or
// one a solution left touching, is settled while it touches (within eps_c); pushed deeper
// (by another group's solution, or left so by a repair) it counts again. In the per-sphere
// models an old link counts again when it is squeezed beyond eps_c, so that its group is
// solved again. With ts.method = "paper" such a pair is in S^{n,q} already and never counts
// again (3.2): only pairs not yet in S are new, whatever the overlap of the others.
template <int D>
std::vector<SpherePair> TimeSteppingEngine<D>::new_overlaps(const State<D>& s, std::vector<int>& moved) {
  sort_unique_ids(moved, s.n_spheres());
  std::vector<std::vector<SpherePair>> found(max_threads());
  const double eps_c = settings_.daha.eps_c;
  contact_pass(s, moved, [&](int i, int j, double d, double sigma) {
    const bool settled = S_.contains(i, j) || round_contacts_.find(i, j) != PairIndex::kAbsent ||
                         (!rigid() && links_.linked(i, j));
    if (settled && (paper() || 1.0 - d / sigma <= eps_c)) return;
    if (rigid() && body_of_sphere(s, i) == body_of_sphere(s, j) && 1.0 - d / sigma <= eps_c) return;
    found[thread_index()].push_back({std::min(i, j), std::max(i, j), 0.0});
  });
  std::vector<SpherePair> pairs;
  for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  sort_unique(pairs, pair_less<SpherePair>);  // found from both ends when both moved
  return pairs;
}

// The clusters, not in `inside` (sorted), that a sphere of `spheres` overlaps by more than
// eps_c. Sorted.
template <int D>
std::vector<std::int32_t> TimeSteppingEngine<D>::clusters_overlapping_outside(const State<D>& s, std::vector<int>& spheres,
                                                                              const std::vector<std::int32_t>& inside) {
  sort_unique_ids(spheres, s.n_spheres());
  const double eps_c = settings_.daha.eps_c;
  std::vector<std::vector<std::int32_t>> found(max_threads());
  contact_pass(s, spheres, [&](int, int j, double d, double sigma) {
    const int cj = s.spheres.cluster[j];
    if (1.0 - d / sigma > eps_c && !std::binary_search(inside.begin(), inside.end(), cj)) found[thread_index()].push_back(cj);
  });
  std::vector<std::int32_t> out;
  for (const auto& f : found) out.insert(out.end(), f.begin(), f.end());
  sort_unique(out);
  return out;
}

#define BALLAGG_TS_CONTACTS(D)                                                                                \
  template std::vector<SpherePair> TimeSteppingEngine<D>::new_overlaps(const State<D>&, std::vector<int>&);  \
  template std::vector<std::int32_t> TimeSteppingEngine<D>::clusters_overlapping_outside(                     \
      const State<D>&, std::vector<int>&, const std::vector<std::int32_t>&);
BALLAGG_TS_CONTACTS(2)
BALLAGG_TS_CONTACTS(3)
#undef BALLAGG_TS_CONTACTS

}  // namespace ballagg
