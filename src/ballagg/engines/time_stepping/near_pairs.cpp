#include "ballagg/engines/time_stepping/near_pairs.hpp"

#include <algorithm>
#include <atomic>
#include <limits>

#include "ballagg/core/parallel.hpp"

namespace ballagg {
namespace {

// When a refresh would query more than this fraction of the spheres, the whole box is
// scanned instead (a half stencil over cells, cheaper per sphere than a query per sphere,
// by about this factor).
constexpr double kFullScanFraction = 0.25;

template <class Pair>
bool pair_equal(const Pair& a, const Pair& b) {
  return a.i == b.i && a.j == b.j;
}

// The pairs found by the threads, sorted and without repeats, in `out`: each thread's
// list sorted on its own thread, then the lists merged. The same list whatever the number
// of threads, and the sorting shared among them.
template <class Pair>
void sorted_union(std::vector<std::vector<Pair>>& parts, std::vector<Pair>& out) {
  const int n_parts = static_cast<int>(parts.size());
  std::size_t total = 0;
  for (const auto& part : parts) total += part.size();
#pragma omp parallel for schedule(static, 1) if (n_parts > 1 && total >= static_cast<std::size_t>(kParallelLoopMin))
  for (int k = 0; k < n_parts; ++k) std::sort(parts[k].begin(), parts[k].end(), pair_less<Pair>);
  out.clear();
  out.reserve(total);
  for (const auto& part : parts) {
    const std::size_t middle = out.size();
    out.insert(out.end(), part.begin(), part.end());
    std::inplace_merge(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(middle), out.end(), pair_less<Pair>);
  }
  out.erase(std::unique(out.begin(), out.end(), pair_equal<Pair>), out.end());
}

}  // namespace

template <int D>
NearPairs<D>::NearPairs(int n_cluster_ids, double skin)
    : skin_(skin),
      travel_(n_cluster_ids, std::numeric_limits<double>::infinity()),
      step_shift_(n_cluster_ids, 0.0) {}

template <int D>
void NearPairs<D>::shifted(int c, double distance) {
  if (step_shift_[c] == 0.0 && distance > 0.0) shifted_.push_back(c);
  step_shift_[c] = std::max(step_shift_[c], distance);
}

template <int D>
void NearPairs<D>::flush_shifts() {
  for (std::int32_t c : shifted_) {
    travel_[c] += step_shift_[c];
    step_shift_[c] = 0.0;
  }
  shifted_.clear();
}

template <int D>
void NearPairs<D>::merged(int a, int b, int into) {
  travel_[into] = std::max(travel_[a], travel_[b]);
}

template <int D>
std::vector<SpherePair> NearPairs<D>::contacts(const State<D>& s, const std::vector<Vec<D>>& positions,
                                               const NearPairCells<D>& cells,
                                               const std::function<void(const std::vector<std::int32_t>&)>& need) {
  std::vector<int> stale_clusters;
  std::size_t n_stale = 0;  // their spheres
  int largest = -1;         // the largest of them
  bool never_listed = false;
  for (int c : s.alive_clusters()) {
    if (!stale(c)) continue;
    never_listed = never_listed || travel_[c] == std::numeric_limits<double>::infinity();
    stale_clusters.push_back(c);
    n_stale += static_cast<std::size_t>(s.clusters[c].size());
    if (largest < 0 || s.clusters[c].size() > s.clusters[largest].size()) largest = c;
  }
  // The pairs of the stale clusters are listed again by a query around each stale sphere
  // or, when one stale cluster holds most spheres (late in a run the giant drifts beyond
  // the skin every few steps), around each sphere outside it: its pairs are found from the
  // side of the others. The whole box is scanned when both would query too many spheres.
  const std::size_t n = static_cast<std::size_t>(s.n_spheres());
  const std::size_t outside_largest = largest < 0 ? n : n - static_cast<std::size_t>(s.clusters[largest].size());
  const std::size_t queries = std::min(n_stale, outside_largest);
  if (never_listed || static_cast<double>(queries) > kFullScanFraction * static_cast<double>(n)) {
    scan_all(s, cells.rebuilt());
    ++full_scans_;
  } else if (n_stale > 0) {
    std::vector<char> is_stale(travel_.size(), 0);
    for (int c : stale_clusters) is_stale[c] = 1;
    std::vector<char> queried(travel_.size(), 0);
    std::vector<int> query_spheres;
    query_spheres.reserve(queries);
    auto query = [&](int c) {
      queried[c] = 1;
      query_spheres.insert(query_spheres.end(), s.clusters[c].members.begin(), s.clusters[c].members.end());
    };
    if (outside_largest < n_stale) {
      for (int c : s.alive_clusters())
        if (c != largest) query(c);
      ++outside_scans_;
    } else {
      for (int c : stale_clusters) query(c);
    }
    const typename NearPairCells<D>::Binned binned = cells.current(query_spheres.size());
    refresh(s, binned, positions, is_stale, queried, query_spheres);
    if (binned.lazy_positions) need(listed_spheres());
    for (int c : stale_clusters) travel_[c] = 0.0;
    ++partial_scans_;
  } else {
    need(listed_spheres());
  }
  ++listing_;
  listed_at_.resize(s.n_spheres(), -1);
  return test_listed(s, positions);
}

// Tests the listed pairs; those now inside one cluster (merged) are dropped for good. In
// pieces of kTestPiece pairs, on several threads when they are many (the list of a large
// run holds millions): each piece keeps its pairs at its own start and finds its touching
// pairs, and the pieces are then joined in order, as one loop would leave them.
template <int D>
std::vector<SpherePair> NearPairs<D>::test_listed(const State<D>& s, const std::vector<Vec<D>>& positions) {
  constexpr std::size_t kTestPiece = 1 << 16;  // pairs per piece: enough to outweigh a task's start
  const std::size_t n_pairs = pairs_.size();
  const std::int64_t n_pieces = static_cast<std::int64_t>((n_pairs + kTestPiece - 1) / kTestPiece);
  std::vector<std::size_t> kept(n_pieces, 0);
  std::vector<std::vector<SpherePair>> touching(n_pieces);
#pragma omp parallel for schedule(dynamic) if (n_pieces > 1)
  for (std::int64_t piece = 0; piece < n_pieces; ++piece) {
    const std::size_t begin = static_cast<std::size_t>(piece) * kTestPiece, end = std::min(n_pairs, begin + kTestPiece);
    std::size_t at = begin;
    for (std::size_t k = begin; k < end; ++k) {
      const Pair p = pairs_[k];
      if (s.spheres.cluster[p.i] == s.spheres.cluster[p.j]) continue;
      pairs_[at++] = p;
      // Two pieces may mark one sphere, with the same value.
      std::atomic_ref<std::int32_t>(listed_at_[p.i]).store(listing_, std::memory_order_relaxed);
      std::atomic_ref<std::int32_t>(listed_at_[p.j]).store(listing_, std::memory_order_relaxed);
      const double contact = s.spheres.radius[p.i] + s.spheres.radius[p.j];
      if (s.box.separation(positions[p.i], positions[p.j]).squaredNorm() <= contact * contact)
        touching[piece].push_back({p.i, p.j, 0.0});
    }
    kept[piece] = at - begin;
  }
  std::size_t size = 0;
  for (std::int64_t piece = 0; piece < n_pieces; ++piece) {
    const auto first = pairs_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(piece) * kTestPiece);
    std::move(first, first + static_cast<std::ptrdiff_t>(kept[piece]), pairs_.begin() + static_cast<std::ptrdiff_t>(size));
    size += kept[piece];
  }
  pairs_.resize(size);
  std::vector<SpherePair> out;
  for (auto& t : touching) out.insert(out.end(), t.begin(), t.end());
  return out;
}

template <int D>
void NearPairs<D>::scan_all(const State<D>& s, const SortedCellList<D>& cells) {
  const std::vector<std::int32_t>& order = cells.order();
  const int n = static_cast<int>(order.size());
  // Cluster ids in slot order, so that the scan below reads contiguous memory only.
  std::vector<std::int32_t> cluster_of_slot(n);
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
  for (int k = 0; k < n; ++k) cluster_of_slot[k] = s.spheres.cluster[order[k]];
  const double reach = 2.0 * s.max_radius() + skin_;  // exact test below when radii differ
  std::vector<std::vector<Pair>> found(max_threads());
  // The cell list holds the spheres at `positions`, in slot order: contiguous reads.
  auto test = [&](std::int32_t k, std::int32_t m, std::vector<Pair>& out) {
    if (cluster_of_slot[m] == cluster_of_slot[k]) return;
    const double d2 = s.box.separation(cells.sorted_position(k), cells.sorted_position(m)).squaredNorm();
    if (d2 > reach * reach) return;
    const int i = order[k], j = order[m];
    const double near = s.spheres.radius[i] + s.spheres.radius[j] + skin_;
    if (d2 <= near * near) out.push_back({std::min(i, j), std::max(i, j)});
  };
  if (!cells.cell_pairs_are_distinct()) {  // tiny periodic box: per sphere, each pair once
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
    for (int k = 0; k < n; ++k)
      cells.for_each_slot_near(cells.sorted_position(k), [&](std::int32_t m) {
        if (m > k) test(k, m, found[thread_index()]);
      });
  } else {
    // Half stencil over cells. A cell whose spheres all belong to one cluster is skipped
    // against itself and against another such cell of the same cluster: the inside of a
    // big aggregate costs one comparison per cell pair.
    const std::int64_t n_cells = cells.n_cells();
    std::vector<std::int32_t> sole(n_cells, -1);  // per cell: its only cluster, or -1
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
    for (std::int64_t c = 0; c < n_cells; ++c) {
      const std::int32_t first = cells.first_slot(c), last = cells.first_slot(c + 1);
      if (first == last) continue;
      std::int32_t id = cluster_of_slot[first];
      for (std::int32_t k = first + 1; k < last && id >= 0; ++k)
        if (cluster_of_slot[k] != id) id = -1;
      sole[c] = id;
    }
    const int chunks = 8 * max_threads();
#pragma omp parallel for schedule(dynamic) if (n >= kParallelLoopMin)
    for (int chunk = 0; chunk < chunks; ++chunk) {
      std::vector<Pair>& mine = found[thread_index()];
      cells.for_each_cell_pair(n_cells * chunk / chunks, n_cells * (chunk + 1) / chunks,
                               [&](std::int64_t a, std::int64_t b) {
        if (sole[a] >= 0 && sole[a] == sole[b]) return;
        const std::int32_t a_end = cells.first_slot(a + 1), b_end = cells.first_slot(b + 1);
        for (std::int32_t k = cells.first_slot(a); k < a_end; ++k)
          for (std::int32_t m = a == b ? k + 1 : cells.first_slot(b); m < b_end; ++m) test(k, m, mine);
      });
    }
  }
  sorted_union(found, pairs_);  // whatever the number of threads
  std::fill(travel_.begin(), travel_.end(), 0.0);
}

// Lists again every pair with a sphere of a stale cluster, by a query around each sphere
// of the queried clusters (the stale ones, or every cluster but the largest stale one; a
// pair is found from a queried side, and once). A sphere within sigma + skin of sphere i
// is binned within sigma + skin + slack of i.
template <int D>
void NearPairs<D>::refresh(const State<D>& s, const typename NearPairCells<D>::Binned& cells,
                           const std::vector<Vec<D>>& positions,
                           const std::vector<char>& is_stale, const std::vector<char>& queried,
                           const std::vector<int>& query_spheres) {
  auto position = [&](int i) -> Vec<D> { return cells.lazy_positions ? s.position(i, s.time) : positions[i]; };
  std::erase_if(pairs_, [&](const Pair& p) {
    return is_stale[s.spheres.cluster[p.i]] || is_stale[s.spheres.cluster[p.j]];
  });
  std::vector<std::vector<Pair>> found(max_threads());
  const std::int64_t n = static_cast<std::int64_t>(query_spheres.size());
  const double reach = 2.0 * s.max_radius() + skin_ + cells.slack;
#pragma omp parallel for schedule(dynamic, 256) if (n >= kParallelLoopMin)
  for (std::int64_t k = 0; k < n; ++k) {
    const int i = query_spheres[k];
    const int ci = s.spheres.cluster[i];
    std::vector<Pair>& mine = found[thread_index()];
    const Vec<D> at = position(i);
    cells.list.for_each_near_segment(at, Vec<D>::Zero(), reach, [&](int j) {
      const int cj = s.spheres.cluster[j];
      if (cj == ci || !(is_stale[ci] || is_stale[cj])) return;  // same cluster, or still listed
      if (queried[cj] && j < i) return;                           // found from j's side
      const double near = s.spheres.radius[i] + s.spheres.radius[j] + skin_;
      if (s.box.separation(at, position(j)).squaredNorm() <= near * near)
        mine.push_back({std::min(i, j), std::max(i, j)});
    });
  }
  std::vector<Pair> fresh;
  sorted_union(found, fresh);  // repeats: tiny periodic boxes
  const std::size_t old_size = pairs_.size();
  pairs_.insert(pairs_.end(), fresh.begin(), fresh.end());
  std::inplace_merge(pairs_.begin(), pairs_.begin() + static_cast<std::ptrdiff_t>(old_size), pairs_.end(),
                     pair_less<Pair>);
}

// The spheres of the listed pairs (with repeats).
template <int D>
std::vector<std::int32_t> NearPairs<D>::listed_spheres() const {
  std::vector<std::int32_t> listed;
  listed.reserve(2 * pairs_.size());
  for (const Pair& p : pairs_) listed.insert(listed.end(), {p.i, p.j});
  return listed;
}

template class NearPairs<2>;
template class NearPairs<3>;

}  // namespace ballagg
