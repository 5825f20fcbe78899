#include "ballagg/engines/time_stepping/time_stepping_engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>

#include "ballagg/core/disjoint_sets.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/engines/time_stepping/minimisation_problem.hpp"
#include "ballagg/engines/time_stepping/time_step_rule.hpp"
#include "ballagg/engines/time_stepping/walls.hpp"
#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {
namespace {

// Cells of the step's cell list are (2 + kGridMargin) R_max wide: spheres may move by
// kGridMargin R_max during the minimisation before the list must be rebuilt.
constexpr double kGridMargin = 1.0;

// Pairs of S in one round above which its groups are solved on several threads.
constexpr std::size_t kParallelPairs = 2000;

std::uint64_t pair_key(int i, int j) {
  if (i > j) std::swap(i, j);
  return (static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j);
}

// The clusters of the spheres of the pairs, sorted, each once.
template <int D>
std::vector<std::int32_t> clusters_of(const State<D>& s, const std::vector<SpherePair>& pairs) {
  std::vector<std::int32_t> out;
  for (const SpherePair& p : pairs) {
    out.push_back(s.spheres.cluster[p.i]);
    out.push_back(s.spheres.cluster[p.j]);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

template <int D>
class TimeSteppingEngine final : public Engine<D> {
 public:
  explicit TimeSteppingEngine(const TimeSteppingSettings& settings) : settings_(settings) {}
  std::string_view name() const override { return "ts"; }
  RunResult run(State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) override;

 private:
  void advect(State<D>& s, double dt);
  void bin(const State<D>& s);
  std::vector<SpherePair> overlapping_pairs(const State<D>& s) const;
  int resolve(State<D>& s, std::vector<SpherePair> S);
  GroupSolution<D> solve_or_place(const ProblemContext<D>& ctx, const CollisionGroup& group) const;
  ProblemContext<D> context(const State<D>& s, const std::vector<SpherePair>& S) const {
    return {s, positions_, step_shift_, flight_, *cells_, cell_slack_, S, links_, settings_, length_scale_, delta_w_, mean_mass_};
  }
  std::vector<CollisionGroup> groups(const State<D>& s, const std::vector<SpherePair>& S,
                                     const std::vector<char>& dirty_pair);
  void apply(const GroupSolution<D>& g, const CollisionGroup& group, std::vector<SpherePair>& S,
             std::unordered_map<std::uint64_t, std::int32_t>& in_S, std::vector<int>& moved);
  template <class F>
  void for_each_contact(const State<D>& s, std::vector<int>& spheres, F&& f) const;
  double largest_overlap(const State<D>& s, std::vector<int>& spheres) const;
  int find_new_pairs(const State<D>& s, std::vector<int>& moved, std::vector<SpherePair>& S,
                     std::unordered_map<std::uint64_t, std::int32_t>& in_S, std::vector<char>& dirty_pair);
  int commit(State<D>& s, const std::vector<SpherePair>& S);

  TimeSteppingSettings settings_;
  EngineCounters counters_;
  std::optional<Box<D>> box_;
  std::vector<Vec<D>> positions_;       // sphere centres at the current time, in the box
  std::vector<Vec<D>> step_shift_;      // displacement of each sphere by this step's minimisation
  std::vector<Vec<D>> flight_;          // displacement of each cluster by this step's free flight
  std::optional<SortedCellList<D>> cells_;
  double cell_slack_ = 0.0;             // how far a sphere may move before re-binning
  bool stale_cells_ = false;            // some sphere moved farther than that this step
  AdhesiveLinks links_;
  DisjointSets sets_;
  std::vector<std::int32_t> group_of_root_;  // per cluster id: index of its group in groups()
  double length_scale_ = 1.0, delta_w_ = 0.0, mean_mass_ = 1.0;
};

template <int D>
RunResult TimeSteppingEngine<D>::run(State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) {
  using clock = std::chrono::steady_clock;
  const auto started = clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(clock::now() - started).count(); };
  const int n = s.n_spheres();
  box_ = s.box;
  length_scale_ = 2.0 * s.mean_radius();
  delta_w_ = settings_.delta_w.value_or(4.0 * s.mean_radius());
  mean_mass_ = s.total_mass() / n;
  positions_.resize(n);
  step_shift_.assign(n, Vec<D>::Zero());
  cells_.emplace(s.box, (2.0 + kGridMargin) * s.max_radius(), n);
  cell_slack_ = cells_->cell_size() - 2.0 * s.max_radius();
  if (settings_.model != TsModel::rigid) links_ = AdhesiveLinks(n);
  sets_ = DisjointSets(static_cast<int>(s.clusters.size()));
  group_of_root_.assign(s.clusters.size(), -1);
  const TimeStepRule rule(settings_, s);

  RunResult result;
  observer.on_start(s);
  while (true) {
    if (s.n_clusters() <= stop.clusters) { result.reason = StopReason::clusters; break; }
    if (elapsed() >= stop.wall_seconds) { result.reason = StopReason::wall_seconds; break; }
    if (s.time >= stop.time) { result.reason = StopReason::time; break; }
    const double dt = rule.next(s);
    if (dt <= 0.0 || (counters_.steps % 64 == 0 && collisions_impossible(s))) {
      result.reason = StopReason::no_collision_possible;
      if (stop.time < kNever) { observer.before_event(s, stop.time); s.time = stop.time; }
      break;
    }
    const double t = std::min(s.time + dt, stop.time);
    observer.before_event(s, t);
    advect(s, t - s.time);
    bin(s);
    const int merges = resolve(s, overlapping_pairs(s));
    ++counters_.steps;
    ++counters_.events;
    EventRecord record;
    record.time = s.time;
    record.kind = EventKind::time_step;
    record.merges = merges;
    observer.after_event(s, record, counters_);
  }
  // The final state lies inside the walls (the last minimisation may have pushed a cluster
  // through one; the next step would have moved it back).
  if (!s.box.periodic())
    for (int c : s.alive_clusters()) keep_inside_walls(s, c, s.time, false);
  result.counters = counters_;
  result.wall_seconds = elapsed();
  observer.on_finish(s, result);
  return result;
}

// Step 1 and 2: free flight (positions are lazy: O(1) per cluster), then walls.
// Records each cluster's displacement (walls included), the way back for backtracking.
template <int D>
void TimeSteppingEngine<D>::advect(State<D>& s, double dt) {
  const double before = s.time;
  s.time += dt;
  flight_.resize(s.clusters.size());
  for (int c : s.alive_clusters()) {
    const Vec<D> start = s.origin(c, before);
    if (!s.box.periodic() && keep_inside_walls(s, c, s.time)) ++counters_.wall_bounces;
    flight_[c] = s.origin(c, s.time) - start;
  }
}

template <int D>
void TimeSteppingEngine<D>::bin(const State<D>& s) {
  const int n = s.n_spheres();
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) positions_[i] = s.position(i, s.time);
  cells_->build(positions_);
}

// Step 3: pairs of spheres of different clusters that overlap or touch (phi >= 0).
template <int D>
std::vector<SpherePair> TimeSteppingEngine<D>::overlapping_pairs(const State<D>& s) const {
  const SortedCellList<D>& cells = *cells_;
  const std::vector<std::int32_t>& order = cells.order();
  const int n = static_cast<int>(order.size());
  // Cluster ids in slot order, so that the scan below reads contiguous memory only.
  std::vector<std::int32_t> cluster_of_slot(n);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k) cluster_of_slot[k] = s.spheres.cluster[order[k]];
  const double reach2 = 4.0 * s.max_radius() * s.max_radius();  // exact test below when radii differ
  std::vector<std::vector<SpherePair>> found(max_threads());
  auto test = [&](std::int32_t k, std::int32_t m, std::vector<SpherePair>& out) {
    if (cluster_of_slot[m] == cluster_of_slot[k]) return;
    const double d2 = s.box.separation(cells.sorted_position(k), cells.sorted_position(m)).squaredNorm();
    if (d2 > reach2) return;
    const int i = order[k], j = order[m];
    const double contact = s.spheres.radius[i] + s.spheres.radius[j];
    if (d2 <= contact * contact) out.push_back({std::min(i, j), std::max(i, j), 0.0});
  };
  if (!cells.cell_pairs_are_distinct()) {  // tiny periodic box: per sphere, each pair once
#pragma omp parallel for schedule(static)
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
#pragma omp parallel for schedule(static)
    for (std::int64_t c = 0; c < n_cells; ++c) {
      const std::int32_t first = cells.first_slot(c), last = cells.first_slot(c + 1);
      if (first == last) continue;
      std::int32_t id = cluster_of_slot[first];
      for (std::int32_t k = first + 1; k < last && id >= 0; ++k)
        if (cluster_of_slot[k] != id) id = -1;
      sole[c] = id;
    }
    const int chunks = 8 * max_threads();
#pragma omp parallel for schedule(dynamic)
    for (int chunk = 0; chunk < chunks; ++chunk) {
      std::vector<SpherePair>& mine = found[thread_index()];
      cells.for_each_cell_pair(n_cells * chunk / chunks, n_cells * (chunk + 1) / chunks,
                               [&](std::int64_t a, std::int64_t b) {
        if (sole[a] >= 0 && sole[a] == sole[b]) return;
        const std::int32_t a_end = cells.first_slot(a + 1), b_end = cells.first_slot(b + 1);
        for (std::int32_t k = cells.first_slot(a); k < a_end; ++k)
          for (std::int32_t m = a == b ? k + 1 : cells.first_slot(b); m < b_end; ++m) test(k, m, mine);
      });
    }
  }
  std::vector<SpherePair> pairs;
  for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  // Sorted: the same list whatever the number of threads.
  std::sort(pairs.begin(), pairs.end(), [](const SpherePair& a, const SpherePair& b) {
    return a.i != b.i ? a.i < b.i : a.j < b.j;
  });
  return pairs;
}

// Step 4: the loop (3.1)-(3.2). Minimise over S, add the pairs the minimisation brought
// into contact, repeat until S stops changing. Groups of clusters joined by S are
// independent problems, solved in parallel; only groups that gained a pair are solved
// again (the others are already at equilibrium). Step 5 (commit) merges and sets the
// velocities.
template <int D>
int TimeSteppingEngine<D>::resolve(State<D>& s, std::vector<SpherePair> S) {
  if (S.empty()) return 0;
  std::unordered_map<std::uint64_t, std::int32_t> in_S;  // pair key -> index in S
  for (std::size_t k = 0; k < S.size(); ++k) in_S.emplace(pair_key(S[k].i, S[k].j), static_cast<std::int32_t>(k));
  std::vector<char> dirty(S.size(), 1);
  std::vector<int> moved, moved_this_step;  // spheres moved in the current round / step
  for (int round = 1;; ++round) {
    const std::vector<CollisionGroup> gs = groups(s, S, dirty);
    const ProblemContext<D> ctx = context(s, S);
    std::vector<GroupSolution<D>> solutions(gs.size());
    std::size_t work = 0;
    for (const CollisionGroup& g : gs) work += g.pairs.size();
    // Threads pay off only when there is enough work to share (starting them costs more
    // than solving a few small groups).
#pragma omp parallel for schedule(dynamic) if (gs.size() > 1 && work >= kParallelPairs)
    for (std::size_t k = 0; k < gs.size(); ++k) solutions[k] = solve_or_place(ctx, gs[k]);
    moved.clear();
    for (std::size_t k = 0; k < gs.size(); ++k) apply(solutions[k], gs[k], S, in_S, moved);
    if (stale_cells_) {  // a sphere moved farther than the cells' slack: bin again
      cells_->build(positions_);
      stale_cells_ = false;
    }
    dirty.assign(S.size(), 0);
    for (const CollisionGroup& g : gs)
      for (int k : g.pairs) { moved.push_back(S[k].i); moved.push_back(S[k].j); }
    moved_this_step.insert(moved_this_step.end(), moved.begin(), moved.end());
    // Only spheres moved in this round can have met new partners.
    if (find_new_pairs(s, moved, S, in_S, dirty) == 0) break;
    ++counters_.link_rounds;
    if (round + 1 >= settings_.max_link_rounds) {
      // Out of rounds: the groups that gained pairs are placed at first contact (no
      // minimisation, so no new contacts among them).
      ++counters_.rounds_exhausted;
      const ProblemContext<D> ctx = context(s, S);
      for (const CollisionGroup& g : groups(s, S, dirty)) apply(place_at_contact(ctx, g), g, S, in_S, moved_this_step);
      break;
    }
  }
  // The largest overlap left around everything this step moved.
  counters_.max_residual_overlap = std::max(counters_.max_residual_overlap, largest_overlap(s, moved_this_step));
  return commit(s, S);
}

// A group whose minimisation does not converge within max_iterations (typically a sphere
// that flew deep into a pocket of another cluster, where no nearby configuration is free of
// overlaps) is moved back to the instant of its first contact instead (place_at_contact).
template <int D>
GroupSolution<D> TimeSteppingEngine<D>::solve_or_place(const ProblemContext<D>& ctx, const CollisionGroup& group) const {
  GroupSolution<D> solution = solve_group(ctx, group);
  if (solution.result.converged) return solution;
  GroupSolution<D> placed = place_at_contact(ctx, group);
  placed.result.iterations = solution.result.iterations;
  return placed;
}

// The connected groups of clusters joined by S that contain a pair marked dirty, each
// listed by increasing cluster id, in the order of their lowest cluster id.
template <int D>
std::vector<CollisionGroup> TimeSteppingEngine<D>::groups(const State<D>& s, const std::vector<SpherePair>& S,
                                                           const std::vector<char>& dirty_pair) {
  const std::vector<std::int32_t> touched = clusters_of(s, S);
  for (int c : touched) sets_.reset(c);
  for (const SpherePair& p : S)
    if (p.active) sets_.unite(s.spheres.cluster[p.i], s.spheres.cluster[p.j]);
  // Only the groups holding a dirty pair are built (the others are at equilibrium).
  for (int c : touched) group_of_root_[sets_.find(c)] = -1;
  std::vector<CollisionGroup> out;
  for (std::size_t k = 0; k < S.size(); ++k) {
    if (!S[k].active || !dirty_pair[k]) continue;
    std::int32_t& g = group_of_root_[sets_.find(s.spheres.cluster[S[k].i])];
    if (g < 0) {
      g = static_cast<std::int32_t>(out.size());
      out.emplace_back();
    }
  }
  for (int c : touched) {
    const std::int32_t g = group_of_root_[sets_.find(c)];
    if (g >= 0) out[g].clusters.push_back(c);  // touched is sorted: clusters come sorted
  }
  for (std::size_t k = 0; k < S.size(); ++k) {
    if (!S[k].active) continue;
    const std::int32_t g = group_of_root_[sets_.find(s.spheres.cluster[S[k].i])];
    if (g >= 0) out[g].pairs.push_back(static_cast<std::int32_t>(k));
  }
  std::sort(out.begin(), out.end(), [](const CollisionGroup& a, const CollisionGroup& b) {
    return a.clusters.front() < b.clusters.front();
  });
  return out;
}

template <int D>
void TimeSteppingEngine<D>::apply(const GroupSolution<D>& g, const CollisionGroup& group, std::vector<SpherePair>& S,
                                  std::unordered_map<std::uint64_t, std::int32_t>& in_S, std::vector<int>& moved) {
  ++counters_.minimisations;
  counters_.daha_iterations += g.result.iterations;
  counters_.max_link_stretch = std::max(counters_.max_link_stretch, g.link_stretch);
  if (g.placed_at_contact) {
    ++counters_.placed_at_contact;
    for (int k : group.pairs) S[k].active = false;
    for (const SpherePair& c : g.contacts) {
      const auto [it, added] = in_S.emplace(pair_key(c.i, c.j), static_cast<std::int32_t>(S.size()));
      if (added) S.push_back(c);
      else S[it->second] = c;
    }
  } else {
    for (std::size_t k = 0; k < group.pairs.size(); ++k) S[group.pairs[k]].lambda = g.pair_lambda[k];
  }
  for (const SpherePair& l : g.old_links) links_.add(l.i, l.j, l.lambda);
  const Box<D>& box = *box_;
  for (std::size_t k = 0; k < g.spheres.size(); ++k) {
    const int i = g.spheres[k];
    positions_[i] = box.wrap(positions_[i] + g.shift[k]);
    step_shift_[i] += g.shift[k];
    stale_cells_ = stale_cells_ || step_shift_[i].norm() > cell_slack_;
    moved.push_back(i);
  }
}

// Calls f(i, j, d, sigma) for every pair of a sphere of `spheres` (sorted, each once) and
// another sphere with phi >= 0 (d <= sigma), spheres of one cluster excepted in the rigid
// model (their distances never change).
template <int D>
template <class F>
void TimeSteppingEngine<D>::for_each_contact(const State<D>& s, std::vector<int>& spheres, F&& f) const {
  std::sort(spheres.begin(), spheres.end());
  spheres.erase(std::unique(spheres.begin(), spheres.end()), spheres.end());
  const bool rigid = settings_.model == TsModel::rigid;
  for (int i : spheres) {
    const int ci = s.spheres.cluster[i];
    cells_->for_each_near(positions_[i], [&](int j) {
      if (j == i || (rigid && s.spheres.cluster[j] == ci)) return;
      const double sigma = s.spheres.radius[i] + s.spheres.radius[j];
      const double d = s.box.separation(positions_[i], positions_[j]).norm();
      if (d <= sigma) f(i, j, d, sigma);
    });
  }
}

// The largest relative overlap between a sphere of `spheres` and any other.
template <int D>
double TimeSteppingEngine<D>::largest_overlap(const State<D>& s, std::vector<int>& spheres) const {
  double largest = 0.0;
  for_each_contact(s, spheres, [&](int, int, double d, double sigma) { largest = std::max(largest, 1.0 - d / sigma); });
  return largest;
}

// (3.2): pairs brought to contact (phi >= 0) by the minimisation, not yet in S nor linked.
template <int D>
int TimeSteppingEngine<D>::find_new_pairs(const State<D>& s, std::vector<int>& moved, std::vector<SpherePair>& S,
                                          std::unordered_map<std::uint64_t, std::int32_t>& in_S,
                                          std::vector<char>& dirty_pair) {
  const bool rigid = settings_.model == TsModel::rigid;
  std::vector<SpherePair> found;
  int reactivated = 0;
  for_each_contact(s, moved, [&](int i, int j, double d, double sigma) {
    const auto known = in_S.find(pair_key(i, j));
    const bool found_now = known != in_S.end() && known->second >= static_cast<std::int32_t>(S.size());
    // An old link squeezed beyond eps_c joins S again, so that its group is solved again.
    const bool settled_link = !rigid && links_.linked(i, j) && 1.0 - d / sigma <= settings_.daha.eps_c;
    if (found_now || (known != in_S.end() && S[known->second].active) || settled_link) return;
    if (known != in_S.end()) {  // replaced by a fall-back placement, overlapping again
      S[known->second].active = true;
      S[known->second].lambda = 0.0;
      dirty_pair[known->second] = 1;
      ++reactivated;
      return;
    }
    in_S.emplace(pair_key(i, j), static_cast<std::int32_t>(S.size() + found.size()));
    found.push_back({std::min(i, j), std::max(i, j), 0.0});
  });
  S.insert(S.end(), found.begin(), found.end());
  dirty_pair.resize(S.size(), 1);
  return static_cast<int>(found.size()) + reactivated;
}

// Step 5: move the state's spheres to their minimised positions, merge the clusters joined
// by S (velocities by rule 2.9, mass-weighted, pair by pair).
template <int D>
int TimeSteppingEngine<D>::commit(State<D>& s, const std::vector<SpherePair>& S) {
  const std::vector<std::int32_t> touched = clusters_of(s, S);  // inactive pairs' too: they moved
  for (int c : touched) {
    const std::vector<std::int32_t>& members = s.clusters[c].members;
    if (settings_.model == TsModel::rigid) {
      const Vec<D> shift = step_shift_[members.front()];
      if (shift != Vec<D>::Zero()) s.translate(c, shift, s.time);
    } else {
      for (int i : members) s.displace_sphere(i, step_shift_[i]);
      s.refresh_extent(c);
    }
    for (int i : members) step_shift_[i].setZero();
  }
  // A pair of S becomes an adhesive link, and merges its clusters, when it touches after
  // the minimisation: d <= sigma (1 + eps_c). (A rigid cluster held by several pairs can
  // settle with some of them apart; those are not contacts.)
  int merges = 0;
  const double reach = 1.0 + settings_.daha.eps_c;
  for (const SpherePair& p : S) {
    if (!p.active) continue;
    const double sigma = s.spheres.radius[p.i] + s.spheres.radius[p.j];
    const double d = s.box.separation(s.unwrapped_position(p.i, s.time), s.unwrapped_position(p.j, s.time)).norm();
    // Apart: not a contact. Overlapping beyond eps_c (only when max_link_rounds ran out):
    // left to the next step rather than frozen into a rigid cluster.
    if (d > reach * sigma || d < (1.0 - settings_.daha.eps_c) * sigma) continue;
    if (settings_.model != TsModel::rigid) links_.add(p.i, p.j, p.lambda);
    if (s.spheres.cluster[p.i] == s.spheres.cluster[p.j]) continue;
    ++counters_.collisions;
    s.merge(p.i, p.j, s.time);
    ++merges;
  }
  counters_.merges += merges;
  // A cluster the minimisation pushed partly through a wall is moved back at the start of
  // the next step, before the overlap detection (moving it now could create overlaps).
  return merges;
}

}  // namespace

template <int D>
std::unique_ptr<Engine<D>> make_time_stepping_engine(const TimeSteppingSettings& settings) {
  return std::make_unique<TimeSteppingEngine<D>>(settings);
}

template std::unique_ptr<Engine<2>> make_time_stepping_engine<2>(const TimeSteppingSettings&);
template std::unique_ptr<Engine<3>> make_time_stepping_engine<3>(const TimeSteppingSettings&);

}  // namespace ballagg
