#include "ballagg/engines/time_stepping/time_stepping_engine.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

#include "ballagg/core/adaptive_team.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/core/prefetch.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/engines/time_stepping/adhesive_set.hpp"
#include "ballagg/engines/time_stepping/flight_sweep.hpp"
#include "ballagg/engines/time_stepping/minimisation_problem.hpp"
#include "ballagg/engines/time_stepping/near_pairs.hpp"
#include "ballagg/engines/time_stepping/repair_waves.hpp"
#include "ballagg/engines/time_stepping/retreat.hpp"
#include "ballagg/engines/time_stepping/step_bodies.hpp"
#include "ballagg/engines/time_stepping/time_step_rule.hpp"
#include "ballagg/spatial/movable_cell_list.hpp"
#include "ballagg/spatial/walls.hpp"

namespace ballagg {
namespace {

// Cells of the step's cell list are (2 + kGridMargin) R_max wide: spheres may move by
// kGridMargin R_max during the minimisation before the list must be rebuilt.
constexpr double kGridMargin = 1.0;

// Steps of zero length at the end of a run that move clusters the last minimisation pushed
// through a wall back inside, and resolve the overlaps this creates.
constexpr int kFinalWallSteps = 8;

// The cell list is rebuilt once more than 1 / kMovedFractionForRebuild of the spheres
// have been moved in it one by one (each move leaves a skipped slot behind).
constexpr std::size_t kMovedFractionForRebuild = 8;

// The cell list is kept from one step to the next: at a step's first use, the spheres of a
// cluster that has drifted more than kBinnedDrift of the cell slack since it was binned
// are binned again (moved in it); the others keep the rest of the slack for the
// minimisations of the step. Late in a run of 10^6 a step meets a few fast fragments and
// a slowly drifting giant, and rebuilding the list at every step that met something was
// half of that phase. Seed 2 of that run: 439 rebuilds with none
// kept, 193 with 0.5, 148 with 0.75 (docs/performance.md, session 13).
constexpr double kBinnedDrift = 0.75;

// Partial refreshes of the near pairs query the cell list as it is binned, more widely,
// while the cells their queries visit since it was last rebuilt number fewer than
// 1 / kWideQueryShare of the spheres (cells_for_queries; what a rebuild would cost, so
// that the widening queries of a long tail never cost much more than rebuilding);
// beyond, the drifted clusters are binned again first.
constexpr double kWideQueryShare = 8.0;

// Lists of sphere ids longer than (number of spheres) / kIdsPerBitmapWord are sorted
// through a bitmap (sort_unique_ids): reading it back costs one word per 64 spheres.
constexpr std::size_t kIdsPerBitmapWord = 64;

// Records of overlaps seen in a step (residual_overlap) that a thread keeps allocated from
// one step to the next; beyond, the memory is given back.
constexpr std::size_t kSightingsKept = std::size_t{1} << 16;

// Pairs in one round above which its groups are solved on several threads.
constexpr std::size_t kParallelPairs = 2000;

// Groups in one wave of fall-backs from which they are repaired on several threads (a
// repair at N = 10^6 takes about 0.2 ms, and a large one shares its own searches among
// the threads when it runs alone).
constexpr std::int64_t kParallelRepairs = 2;

// Spheres moved by one apply() from which they are moved on several threads (scattered
// reads and writes; about 0.2 us a sphere at N = 10^6 with the cell-list moves, measured
// in session 12: a wave of two fall-backs moves hundreds of spheres).
constexpr std::size_t kParallelApply = 1024;

// apply() shares its work among the threads in pieces of at most this many spheres of one
// solution: late in a run of 10^6 a round may apply a single solution that moves a giant
// (10^5 spheres and more), which a loop over whole solutions left on one thread.
constexpr std::size_t kApplyPiece = 4096;

// Sorts and removes repeats.
template <class T, class Less = std::less<T>>
void sort_unique(std::vector<T>& v, Less less = {}) {
  std::sort(v.begin(), v.end(), less);
  v.erase(std::unique(v.begin(), v.end(), [&](const T& a, const T& b) { return !less(a, b) && !less(b, a); }),
          v.end());
}

// Sorts and removes repeats from a list of ids below n. A long list (late in a large run a
// round moves whole clusters: 10^5 spheres and more) is marked in a bitmap and read back in
// order, O(n / 64 + size) instead of a sort; the result is the same.
void sort_unique_ids(std::vector<int>& ids, int n) {
  if (ids.size() < static_cast<std::size_t>(n) / kIdsPerBitmapWord) {
    sort_unique(ids);
    return;
  }
  std::vector<std::uint64_t> bits((static_cast<std::size_t>(n) + 63) / 64, 0);
  for (int i : ids) bits[static_cast<std::size_t>(i) >> 6] |= std::uint64_t{1} << (i & 63);
  ids.clear();
  for (std::size_t w = 0; w < bits.size(); ++w)
    for (std::uint64_t word = bits[w]; word != 0; word &= word - 1)
      ids.push_back(static_cast<int>(64 * w) + std::countr_zero(word));
}


// One step of §3, as named stages: advect (steps 1-2), detect the overlaps (2a), resolve
// them by the loop (3.1)-(3.2) (2b-2e), commit the new clusters and their velocities (3).
template <int D>
class TimeSteppingEngine final : public Engine<D> {
 public:
  TimeSteppingEngine(const TimeSteppingSettings& settings, DahaProblemSink<D>* sink)
      : settings_(settings), sink_(sink) {}
  std::string_view name() const override { return "ts"; }
  RunResult run(State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) override;
  bool supports_checkpoints() const override { return true; }
  void resume_from(State<D>& s, std::string_view saved) override;

 private:
  // Checkpoints, taken between two steps: all a step leaves behind is the counters, the
  // step rule's reference values and the links of the per-sphere models.
  std::string save() const;
  void prepare(const State<D>& s);
  void step(State<D>& s, double t, RunObserver<D>& observer);
  bool outside_walls(const State<D>& s) const;
  void advect(State<D>& s, double dt);
  void defer_positions(const State<D>& s);
  void materialise_positions();
  void materialise_positions(const std::vector<std::int32_t>& spheres);
  void rebin();
  const MovableCellList<D>& binned_cells(const State<D>& s);
  typename NearPairCells<D>::Binned cells_for_queries(const State<D>& s, std::size_t queries);
  void detect_overlaps(const State<D>& s);
  void resolve(const State<D>& s);
  void poll_team() {
    if (team_) team_->poll();
  }
  GroupSolution<D> repair(const StepView<D>& ctx, const CollisionGroup& group) const;
  bool beyond_minimisation(const State<D>& s, const CollisionGroup& group) const;
  std::uint64_t round_signature() const;
  void apply(const State<D>& s, const std::vector<const GroupSolution<D>*>& solutions, std::vector<int>& moved);
  void apply(const State<D>& s, const GroupSolution<D>& solution, std::vector<int>& moved) { apply(s, {&solution}, moved); }
  std::vector<SpherePair> new_overlaps(const State<D>& s, std::vector<int>& moved);
  bool end_round(const State<D>& s, const std::vector<CollisionGroup>& groups,
                 const std::vector<GroupSolution<D>>& solutions, const std::vector<SpherePair>& overlaps);
  void settle(const State<D>& s, const std::vector<SpherePair>& left);
  std::vector<std::int32_t> clusters_overlapping_outside(const State<D>& s, std::vector<int>& spheres,
                                                         const std::vector<std::int32_t>& inside);
  int commit(State<D>& s);
  void commit_moves(State<D>& s, std::vector<std::int32_t>& moved_clusters);
  void commit_rigid_moves(State<D>& s, std::vector<std::int32_t>& moved_clusters);
  template <class F>
  void for_each_contact(const State<D>& s, const std::vector<int>& spheres, F&& f) const;
  template <class F>
  void contact_pass(const State<D>& s, const std::vector<int>& moved, F&& f);
  void forget_outdated_sightings();
  double residual_overlap();

  StepView<D> context(const State<D>& s) const {
    return {.state = s,
            .positions = positions_,
            .step_shift = step_shift_,
            .flight = flight_,
            .bodies = bodies_,
            .cells = *cells_,
            .cell_slack = cell_slack_,
            .S = S_,
            .links = links_,
            .settings = settings_,
            .length_scale = length_scale_,
            .delta_w = delta_w_,
            .mean_mass = mean_mass_,
            .sink = sink_,
            .guard = guard_};
  }
  bool rigid() const { return settings_.model == TsModel::rigid; }
  // Whether sphere i may have moved more than the near list's half skin since its
  // cluster's pairs were listed.
  bool beyond_half_skin(const State<D>& s, int i) const {
    return near_.travel(s.spheres.cluster[i]) + step_shift_[i].norm() > 0.5 * near_.skin();
  }
  void mark_spheres_beyond_skin();
  bool needs_no_contact_query(const State<D>& s, int i) const;
  void forget_spheres_beyond_skin();
  int body_of_sphere(const State<D>& s, int i) const { return bodies_.body_of(s.spheres.cluster[i]); }

  TimeSteppingSettings settings_;
  DahaProblemSink<D>* sink_;
  EngineCounters counters_;
  std::optional<Box<D>> box_;
  std::vector<Vec<D>> positions_;            // sphere centres at the current time, in the box
  const State<D>* positions_of_ = nullptr;   // set: positions_ not yet computed for this step's time
  std::vector<Vec<D>> step_shift_;           // per sphere: its displacement by this step's minimisations
  std::vector<Vec<D>> moved_since_binning_;  // per sphere: this step's moves since it was binned
  std::vector<double> binned_drift_;         // per cluster id: bound on its spheres' moves since binned, before this step's minimisations
  std::vector<double> committed_moves_;      // per cluster id, within commit(): largest move of a sphere since binned
  struct ApplyPiece {
    const GroupSolution<D>* solution;
    std::size_t begin, end;  // its spheres [begin, end)
    std::size_t at;          // where its spheres go in the round's moved list, and in to_rebin_
    std::size_t n_rebin;     // how many of them moved beyond the cell slack (to_rebin_[at, at + n_rebin))
  };
  std::vector<ApplyPiece> apply_pieces_;     // within apply(): the work shared among the threads
  std::vector<std::int32_t> to_rebin_;       // within apply(): per piece, its spheres moved beyond the cell slack
  std::vector<Vec<D>> flight_;               // per cluster: its displacement by this step's free flight
  std::optional<MovableCellList<D>> cells_;
  double cell_slack_ = 0.0;                  // how far a sphere may move before it is re-binned
  bool cells_built_ = false;                 // the cell list has been built since prepare()
  bool cells_binned_ = false;                // every sphere is within the cell slack of where it is binned
  double wide_query_cells_ = 0.0;            // cells visited by widened queries since the list was built
  AdhesiveSet S_;                            // the adhesive set of a round and its groups (of bodies)
  StepBodies bodies_;                        // the clusters of the step, joined by its links
  AdhesiveLinks links_;                      // per-sphere models: the links of the old clusters
  NearPairs<D> near_;                        // pairs of spheres of different clusters that may touch
  PairIndex round_contacts_;                 // the pairs the solutions of a round leave touching
  std::vector<int> moved_in_step_;           // spheres moved by this step's minimisations
  // What the contact passes of the step saw (residual_overlap): per sphere the pass that
  // saw it last moved (-1: not moved in this step), and per thread the pairs seen.
  struct Sighting {
    std::int32_t i, j, pass;
    double overlap;
  };
  std::vector<std::int32_t> last_pass_;
  std::int32_t pass_ = 0;                    // the next contact pass of the step
  std::size_t forget_at_ = kSightingsKept;   // records beyond which the outdated are dropped
  std::vector<std::vector<Sighting>> sightings_;
  // Set: no cluster has moved more than the near-pair list allows since it was listed, so
  // a sphere in no listed pair touches no other cluster (NearPairs::listed).
  bool near_list_complete_ = false;
  // Unset, a sphere in no listed pair whose cluster is still within the half skin can
  // touch only a sphere that a move of this step took beyond it. Per cell of the cell
  // list's grid: kHoldsBeyond, such a move put a sphere there; kBesideBeyond, it is next
  // to such a cell. Cleared at the next detection.
  static constexpr char kHoldsBeyond = 1, kBesideBeyond = 2;
  std::vector<char> beyond_mark_;
  std::vector<std::int32_t> beyond_cells_;               // the cells holding one, to clear them
  std::vector<std::vector<std::int32_t>> beyond_found_;  // per thread, within apply(): their cells
  double length_scale_ = 1.0, delta_w_ = 0.0, mean_mass_ = 1.0;
  std::optional<TimeStepRule> rule_;         // from the state at the start of the run
  RunGuard* guard_ = nullptr;                // the guard of the run under way
  bool resumed_ = false;                     // resume_from prepared the next run()
  AdaptiveTeam* team_ = nullptr;             // during run(): the team of its parallel regions
};

template <int D>
RunResult TimeSteppingEngine<D>::run(State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) {
  RunGuard own_guard(stop.wall_seconds);
  RunGuard& guard = stop.guard != nullptr ? *stop.guard : own_guard;
  guard_ = &guard;
  // The team of the parallel regions, measured between steps and between the stages of a
  // step (the first steps of 10^6 spheres last minutes, docs/performance.md).
  AdaptiveTeam team;
  struct InUse {
    AdaptiveTeam*& slot;
    ~InUse() { slot = nullptr; }
  } in_use{team_ = &team};
  if (!resumed_) {
    prepare(s);
    rule_.emplace(settings_, s);
  }
  resumed_ = false;
  const TimeStepRule& rule = *rule_;

  RunResult result;
  observer.on_start(s);
  while (true) {
    team.poll();
    // A signal: the checkpointing observer writes one and ends the run by throwing.
    guard.check();
    if (guard.cause() != StopCause::wall_seconds && observer.checkpoint_due())
      observer.on_checkpoint(s, counters_, save());
    if (s.n_clusters() <= stop.clusters) { result.reason = StopReason::clusters; break; }
    if (guard.stopped()) { result.reason = stop_reason_of(guard.cause()); break; }
    if (s.time >= stop.time) { result.reason = StopReason::time; break; }
    const double dt = rule.next(s);
    if (dt <= 0.0 || (counters_.steps % 64 == 0 && collisions_impossible(s))) {
      result.reason = StopReason::no_collision_possible;
      if (stop.time < kNever) {
        observer.before_event(s, stop.time);
        if (guard.cause() == StopCause::signal) continue;  // output cut short: checkpoint first
        if (guard.stopped()) result.reason = stop_reason_of(guard.cause());
        s.time = stop.time;
      }
      break;
    }
    step(s, std::min(s.time + dt, stop.time), observer);
  }
  // The final state lies inside the walls. A cluster may have ended the last step a little
  // through one (see commit); the next step would have moved it back and resolved the
  // overlaps that creates, and so do steps of zero length here. Should they not settle, the clusters are
  // moved back all the same (summary.json's max_overlap then shows what is left).
  if (!s.box.periodic() && result.reason != StopReason::interrupted) {
    for (int k = 0; k < kFinalWallSteps && outside_walls(s); ++k) step(s, s.time, observer);
    for (int c : s.alive_clusters()) keep_inside_walls(s, c, s.time, false);
  }
  result.counters = counters_;
  result.wall_seconds = guard.elapsed();
  guard_ = nullptr;
  observer.on_finish(s, result);
  return result;
}

// One step to time t (t = s.time: walls and overlaps only). The observers' output before
// it may be cut short by a signal (RunGuard): the step is then not taken, and the
// checkpoint written next resumes where the output stopped. Cut short otherwise (the
// wall-clock limit, an output cap), the step is taken and the run ends after it, without
// the output that had no time to be written.
template <int D>
void TimeSteppingEngine<D>::step(State<D>& s, double t, RunObserver<D>& observer) {
  observer.before_event(s, t);
  if (guard_->cause() == StopCause::signal) return;
  advect(s, t - s.time);
  defer_positions(s);
  detect_overlaps(s);
  poll_team();
  resolve(s);
  EventRecord record;
  record.merges = commit(s);
  ++counters_.steps;
  ++counters_.events;
  record.time = s.time;
  record.kind = EventKind::time_step;
  observer.after_event(s, record, counters_);
}

template <int D>
bool TimeSteppingEngine<D>::outside_walls(const State<D>& s) const {
  for (int c : s.alive_clusters())
    if (wall_correction(s, c, s.time, false).shift != Vec<D>::Zero()) return true;
  return false;
}

template <int D>
void TimeSteppingEngine<D>::prepare(const State<D>& s) {
  const int n = s.n_spheres();
  const int n_cluster_ids = static_cast<int>(s.clusters.size());
  box_ = s.box;
  length_scale_ = 2.0 * s.mean_radius();
  delta_w_ = settings_.delta_w.value_or(4.0 * s.mean_radius());
  mean_mass_ = s.total_mass() / n;
  positions_.resize(n);
  positions_of_ = nullptr;
  step_shift_.assign(n, Vec<D>::Zero());
  moved_since_binning_.assign(n, Vec<D>::Zero());
  binned_drift_.assign(n_cluster_ids, 0.0);
  committed_moves_.assign(n_cluster_ids, 0.0);
  cells_built_ = false;
  last_pass_.assign(n, -1);
  pass_ = 0;
  forget_at_ = kSightingsKept;
  sightings_.assign(max_threads(), {});
  cells_.emplace(s.box, (2.0 + kGridMargin) * s.max_radius(), n);
  beyond_mark_.assign(static_cast<std::size_t>(cells_->sorted().grid().n_cells()), 0);
  beyond_cells_.clear();
  beyond_found_.assign(max_threads(), {});
  cell_slack_ = cells_->cell_size() - 2.0 * s.max_radius();
  near_ = NearPairs<D>(n_cluster_ids, cell_slack_);
  S_ = AdhesiveSet(n_cluster_ids);
  bodies_ = StepBodies(n_cluster_ids);
  if (!rigid()) links_ = AdhesiveLinks(n);
}

template <int D>
std::string TimeSteppingEngine<D>::save() const {
  ByteWriter w;
  w.put(counters_);
  rule_->save(w);
  w.put<std::int32_t>(static_cast<std::int32_t>(positions_.size()));
  if (!rigid())
    for (std::size_t i = 0; i < positions_.size(); ++i) {
      w.put<std::uint64_t>(links_.of(static_cast<int>(i)).size());
      for (const LinkEnd& e : links_.of(static_cast<int>(i))) {
        w.put(e.other);
        w.put(e.lambda);
      }
    }
  return w.take();
}

template <int D>
void TimeSteppingEngine<D>::resume_from(State<D>& s, std::string_view saved) {
  ByteReader r(saved, "checkpoint of the ts engine");
  prepare(s);
  counters_ = r.get<EngineCounters>("counters");
  rule_.emplace(settings_, s);
  rule_->restore(r);
  const int n = s.n_spheres();
  if (r.get<std::int32_t>("sphere count") != n) r.fail("saved for another number of spheres");
  if (!rigid())
    for (int i = 0; i < n; ++i) {
      const auto links = r.get<std::uint64_t>("link count");
      for (std::uint64_t k = 0; k < links; ++k) {
        const auto other = r.get<std::int32_t>("link");
        const auto lambda = r.get<double>("link multiplier");
        if (other <= i || other >= n) r.fail("a link that names no sphere");
        links_.add(i, other, lambda);
      }
    }
  r.expect_end();
  resumed_ = true;
}

// Steps 1 and 2: free flight (positions are lazy: O(1) per cluster), then walls.
// Records each cluster's displacement (walls included), the way back for a retreat.
template <int D>
void TimeSteppingEngine<D>::advect(State<D>& s, double dt) {
  const double before = s.time;
  s.time += dt;
  flight_.resize(s.clusters.size());
  for (int c : s.alive_clusters()) {
    const Vec<D> start = s.origin(c, before);
    if (!s.box.periodic() && keep_inside_walls(s, c, s.time)) ++counters_.wall_bounces;
    flight_[c] = s.origin(c, s.time) - start;
    near_.travelled(c, flight_[c].norm());
    binned_drift_[c] += flight_[c].norm();
  }
}

// The positions of the step, and the cell list, are computed when a stage needs them. A
// step in which nothing comes near needs neither: late in a large run (a giant and a few
// fragments looking for it, thousands of steps) such a step reads only the listed near
// pairs, and computing 10^6 positions was 42 % of it (docs/performance.md).
template <int D>
void TimeSteppingEngine<D>::defer_positions(const State<D>& s) {
  positions_of_ = &s;
  cells_binned_ = false;
}

// Every sphere's position at the step's time (what defer_positions put off).
template <int D>
void TimeSteppingEngine<D>::materialise_positions() {
  if (positions_of_ == nullptr) return;
  const State<D>& s = *positions_of_;
  const int n = s.n_spheres();
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
  for (int i = 0; i < n; ++i) positions_[i] = s.position(i, s.time);
  positions_of_ = nullptr;
}

// The positions of these spheres only (the same values: State::position at the step's time).
template <int D>
void TimeSteppingEngine<D>::materialise_positions(const std::vector<std::int32_t>& spheres) {
  if (positions_of_ == nullptr) return;
  for (std::int32_t i : spheres) positions_[i] = positions_of_->position(i, positions_of_->time);
}

// The cell list at the step's first use: the spheres of the clusters that drifted more than
// kBinnedDrift of the slack since binned are binned again, or, when they are many, every
// sphere (rebin).
template <int D>
const MovableCellList<D>& TimeSteppingEngine<D>::binned_cells(const State<D>& s) {
  if (cells_binned_) return *cells_;
  materialise_positions();
  std::vector<int> drifted;
  std::size_t to_move = cells_->n_moved();
  if (cells_built_)
    for (int c : s.alive_clusters())
      if (binned_drift_[c] > kBinnedDrift * cell_slack_) {
        drifted.push_back(c);
        to_move += static_cast<std::size_t>(s.clusters[c].size());
      }
  if (!cells_built_ || to_move * kMovedFractionForRebuild > positions_.size()) {
    rebin();
    return *cells_;
  }
  for (int c : drifted) {
    for (int i : s.clusters[c].members) cells_->move(i, positions_[i]);
    binned_drift_[c] = 0.0;
  }
  cells_binned_ = true;
  return *cells_;
}

// The cell list for the queries of a partial refresh of the near pairs (detect_overlaps),
// and how far a sphere may be from where it is binned. A few queries look wider, by the
// largest drift of a cluster since it was binned, instead of binning the drifted clusters
// again: late in a large run the queries are made around the few spheres outside a giant
// that has drifted past the near list's half skin, and binning the giant again was a
// rebuild of the whole list every few dozen steps (in a run of 10^6 whose last two
// clusters, a giant and two spheres, took 340 000 steps to meet, 82 % of each step;
// docs/performance.md, session 19). The list is left as it is: the step's later stages
// bin what they need (binned_cells). The pairs found are the same either way.
template <int D>
typename NearPairCells<D>::Binned TimeSteppingEngine<D>::cells_for_queries(const State<D>& s, std::size_t queries) {
  if (cells_built_ && !cells_binned_) {
    double drift = kBinnedDrift * cell_slack_;
    for (int c : s.alive_clusters()) drift = std::max(drift, binned_drift_[c]);
    // The cells the widened queries visit, against a rebuild's passes over every sphere.
    const double reach = (2.0 * s.max_radius() + near_.skin() + drift) / cells_->cell_size();
    const double cells = static_cast<double>(queries) * std::pow(2.0 * std::ceil(reach) + 1.0, D);
    if ((wide_query_cells_ + cells) * kWideQueryShare <= static_cast<double>(s.n_spheres())) {
      wide_query_cells_ += cells;
      // Nor are the positions of every sphere filled for so few queries.
      return {*cells_, drift, positions_of_ != nullptr};
    }
  }
  return {binned_cells(s), kBinnedDrift * cell_slack_, false};
}

// Bins every sphere at its position now.
template <int D>
void TimeSteppingEngine<D>::rebin() {
  materialise_positions();
  cells_->build(positions_);
  cells_built_ = cells_binned_ = true;
  wide_query_cells_ = 0.0;
  std::fill(moved_since_binning_.begin(), moved_since_binning_.end(), Vec<D>::Zero());
  std::fill(binned_drift_.begin(), binned_drift_.end(), 0.0);
}

// Step 2a: S starts as the pairs of spheres of different clusters that overlap or touch
// (phi >= 0) after the free flight, found among the near pairs (near_pairs.hpp).
template <int D>
void TimeSteppingEngine<D>::detect_overlaps(const State<D>& s) {
  // A scan of the whole box reads the list in slot order: it is built afresh. A partial
  // refresh is made before the step's minimisations, when every sphere is within
  // kBinnedDrift of the cell slack of where it is binned.
  const NearPairCells<D> cells{[&]() -> const SortedCellList<D>& {
                                 rebin();
                                 return cells_->sorted();
                               },
                               [&](std::size_t queries) { return cells_for_queries(s, queries); }};
  const auto need = [this](const std::vector<std::int32_t>& spheres) { materialise_positions(spheres); };
  const std::vector<SpherePair> touching = near_.contacts(s, positions_, cells, need);
  S_.add_all(touching, s.spheres.cluster);
  near_list_complete_ = true;  // every cluster is within skin / 2 of its listing now
  forget_spheres_beyond_skin();
}

// Steps 2b-2e, the loop (3.1)-(3.2). Each round minimises every group of S (the bodies
// joined by S), links the pairs the solutions leave touching (their bodies move as one
// from then on), and takes as the next S the pairs the minimisation brought into contact.
// An overlap inside a body dissolves it: its links rejoin S with that overlap, and its
// clusters are solved again separately. The loop ends when a round brings no new contact;
// max_link_rounds bounds it.
template <int D>
void TimeSteppingEngine<D>::resolve(const State<D>& s) {
  if (S_.empty()) return;
  binned_cells(s);
  std::vector<int> moved;
  std::vector<std::uint64_t> earlier_rounds;  // their signatures
  for (int round = 1;; ++round) {
    const std::vector<CollisionGroup> groups = S_.take_changed_groups();
    if (groups.empty()) break;
    poll_team();
    if (round > 1) ++counters_.link_rounds;
    // A round with the adhesive set of an earlier round of this step would go on repeating
    // the rounds since (a cycle: at N = 10^6 a few groups took turns, solved, retreated and
    // solved again, with a period of six rounds until max_link_rounds): it ends the loop as
    // the last round would.
    const std::uint64_t signature = round_signature();
    const bool repeats = std::find(earlier_rounds.begin(), earlier_rounds.end(), signature) != earlier_rounds.end();
    earlier_rounds.push_back(signature);
    // A step that must end (RunGuard::step_must_end: the wall-clock limit, or a signal that
    // has waited) ends as at max_link_rounds: the groups left go to the fall-back.
    const bool out_of_rounds =
        round >= settings_.max_link_rounds || repeats || (guard_ != nullptr && guard_->step_must_end());
    if (out_of_rounds) ++counters_.rounds_exhausted;
    const StepView<D> ctx = context(s);
    std::vector<GroupSolution<D>> solutions(groups.size());
    std::size_t work = 0;
    for (const CollisionGroup& g : groups) work += g.pairs.size();
    // Threads pay off only when there is enough work to share (starting them costs more
    // than solving a few small groups).
    if (!out_of_rounds) {
#pragma omp parallel for schedule(dynamic) if (groups.size() > 1 && work >= kParallelPairs)
      for (std::size_t k = 0; k < groups.size(); ++k)
        if (!beyond_minimisation(s, groups[k])) solutions[k] = solve_group(ctx, groups[k]);
    }
    moved.clear();
    std::vector<const GroupSolution<D>*> solved;
    for (const GroupSolution<D>& solution : solutions)
      if (solution.result.converged) solved.push_back(&solution);
    apply(s, solved, moved);
    // The groups the minimisation did not solve are repaired one after the other, each
    // seeing where everything else has gone, in the order of repair_waves.hpp; those that
    // cannot see each other at once, wave by wave (the same answers).
    std::vector<std::size_t> failed;
    for (std::size_t k = 0; k < groups.size(); ++k)
      if (!solutions[k].result.converged) failed.push_back(k);
    for (const std::vector<std::size_t>& wave : repair_waves(ctx, groups, failed)) {
      poll_team();
      const std::int64_t n_wave = static_cast<std::int64_t>(wave.size());
#pragma omp parallel for schedule(dynamic) if (n_wave >= kParallelRepairs)
      for (std::int64_t w = 0; w < n_wave; ++w) {
        const std::size_t k = wave[w];
        const int iterations = solutions[k].result.iterations;
        solutions[k] = repair(ctx, groups[k]);
        solutions[k].result.iterations += iterations;
      }
      std::vector<const GroupSolution<D>*> repaired;
      for (std::size_t k : wave) repaired.push_back(&solutions[k]);
      apply(s, repaired, moved);
    }
    moved_in_step_.insert(moved_in_step_.end(), moved.begin(), moved.end());
    if (out_of_rounds) {
      end_round(s, groups, solutions, {});
      S_.clear();
      settle(s, new_overlaps(s, moved));
      break;
    }

    round_contacts_.clear();
    for (const GroupSolution<D>& g : solutions)
      for (const SpherePair& c : g.contacts) round_contacts_.insert(c.i, c.j, 0);
    if (!end_round(s, groups, solutions, new_overlaps(s, moved))) {
      ++counters_.rounds_exhausted;  // stalled: what is left overlapping is settled
      const std::vector<SpherePair> left = S_.pairs();
      S_.clear();
      settle(s, left);
      break;
    }
  }
  counters_.max_residual_overlap = std::max(counters_.max_residual_overlap, residual_overlap());
}

// The fall-back for a group the minimisation did not solve: every cluster of its bodies
// moved back along its own flight (see retreat.hpp) and, with keep-flight, on again to the
// end of the step, merging at each contact (flight_sweep.hpp). The bodies are dissolved
// first: the retreat undoes what joined them.
template <int D>
GroupSolution<D> TimeSteppingEngine<D>::repair(const StepView<D>& ctx, const CollisionGroup& group) const {
  if (settings_.fall_back == TsFallBack::keep_flight) return keep_flight(ctx, group);
  return place_at_contact(ctx, group);
}

// Whether a group is left to the fall-back without trying a minimisation: retreat_pairs
// pairs of S or more (clusters flown deep into each other), or a pair of S overlapping by
// retreat_overlap or more (centres nearly on top of each other: a sphere flew through
// another, and no nearby configuration says from which side it came; off by default). At
// N = 10^6 late in a run, groups of 64 pairs or more converged in 2 cases out of 746 and
// took 85 % of the DAHA's work (docs/time_stepping.md). Rigid model only: in the
// per-sphere models S also holds the clusters' own squeezed links, and the rules were
// neither measured there nor safe (a 3D test of the non-rigid model then left overlaps).
template <int D>
bool TimeSteppingEngine<D>::beyond_minimisation(const State<D>& s, const CollisionGroup& g) const {
  if (!rigid()) return false;
  if (static_cast<int>(g.pairs.size()) >= settings_.retreat_pairs) return true;
  for (int k : g.pairs) {
    const SpherePair& p = S_.pairs()[k];
    const double sigma = s.spheres.radius[p.i] + s.spheres.radius[p.j];
    if (1.0 - s.box.separation(positions_[p.i], positions_[p.j]).norm() / sigma >= settings_.retreat_overlap) return true;
  }
  return false;
}

// A hash of the adhesive set of the round, its pairs in order and where their spheres are
// (to the bit): the same pairs at the same places make the same round again. (The pairs
// alone are not enough: in the per-sphere models a round can meet the pairs of an earlier
// one with its clusters deformed since, and go on to solve them.)
template <int D>
std::uint64_t TimeSteppingEngine<D>::round_signature() const {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a
  auto mix = [&](std::uint64_t word) {
    h ^= word;
    h *= 1099511628211ull;
  };
  for (const SpherePair& p : S_.pairs())
    for (std::int32_t id : {p.i, p.j}) {
      mix(static_cast<std::uint32_t>(id));
      for (int a = 0; a < D; ++a) mix(std::bit_cast<std::uint64_t>(positions_[id][a]));
    }
  return h;
}

// Moves the spheres of these solutions in positions_ (the state is moved at commit). The
// solutions move disjoint spheres: on several threads, in pieces of kApplyPiece spheres,
// when they are many (early in a run of 10^6 a round applies 10^5 solutions, late in it one
// solution may move a giant); the cell list is then updated in solution order.
template <int D>
void TimeSteppingEngine<D>::apply(const State<D>& s, const std::vector<const GroupSolution<D>*>& solutions,
                                  std::vector<int>& moved) {
  std::size_t n_moved = 0;
  for (const GroupSolution<D>* g : solutions) {
    ++counters_.minimisations;
    counters_.daha_iterations += g->result.iterations;
    counters_.max_link_stretch = std::max(counters_.max_link_stretch, g->link_stretch);
    if (g->placed_at_contact) ++counters_.placed_at_contact;
    for (const SpherePair& l : g->old_links) links_.add(l.i, l.j, l.lambda);
    n_moved += g->spheres.size();
  }
  const Box<D>& box = *box_;
  const GridGeometry<D>& grid = cells_->sorted().grid();
  const bool mark_beyond = rigid();  // only the rigid model's contact checks read the marks
  apply_pieces_.clear();
  std::size_t at = 0;
  for (const GroupSolution<D>* g : solutions)
    for (std::size_t begin = 0; begin < g->spheres.size(); begin += kApplyPiece) {
      const std::size_t end = std::min(g->spheres.size(), begin + kApplyPiece);
      apply_pieces_.push_back({g, begin, end, at, 0});
      at += end - begin;
    }
  // The moved list and the spheres to bin again are filled by the pieces, each in its own
  // range (the work on every moved sphere shared, late in a large run 10^5 spheres a round).
  const std::size_t first_moved = moved.size();
  moved.resize(first_moved + n_moved);
  to_rebin_.resize(n_moved);
  bool beyond_skin = false;
  const std::int64_t n_pieces = static_cast<std::int64_t>(apply_pieces_.size());
  const int chunk = static_cast<int>(std::clamp<std::int64_t>(n_pieces / 64, 1, 64));
  fit_to_team(beyond_found_);
#pragma omp parallel for schedule(dynamic, chunk) reduction(|| : beyond_skin) \
    if (n_pieces > 1 && n_moved >= kParallelApply)
  for (std::int64_t k = 0; k < n_pieces; ++k) {
    ApplyPiece& piece = apply_pieces_[k];
    const GroupSolution<D>& g = *piece.solution;
    for (std::size_t m = piece.begin; m < piece.end; ++m) {
      // The spheres of a solution are scattered over the arrays (a giant's members late in
      // a run): their entries are asked for ahead, or each sphere waits for five loads.
      prefetch_entries(g.spheres, m + kPrefetchAhead, positions_, step_shift_, moved_since_binning_, last_pass_,
                       s.spheres.cluster);
      const int i = g.spheres[m];
      positions_[i] = box.wrap(positions_[i] + g.shift[m]);
      step_shift_[i] += g.shift[m];
      last_pass_[i] = pass_;
      if (beyond_half_skin(s, i)) {
        beyond_skin = true;
        // The spheres of a cluster come one after the other, many in the same cell.
        if (mark_beyond) {
          std::vector<std::int32_t>& found = beyond_found_[thread_index()];
          const std::int32_t cell = grid.cell_index(positions_[i]);
          if (found.empty() || found.back() != cell) found.push_back(cell);
        }
      }
      moved_since_binning_[i] += g.shift[m];
      moved[first_moved + piece.at + (m - piece.begin)] = i;
      if (binned_drift_[s.spheres.cluster[i]] + moved_since_binning_[i].norm() > cell_slack_)
        to_rebin_[piece.at + piece.n_rebin++] = i;
    }
  }
  if (beyond_skin) near_list_complete_ = false;
  mark_spheres_beyond_skin();
  // In the order of the spheres in the solutions, as the pieces come.
  for (const ApplyPiece& piece : apply_pieces_)
    for (std::size_t r = piece.at; r < piece.at + piece.n_rebin; ++r) {
      const int i = to_rebin_[r];
      cells_->move(i, positions_[i]);
      moved_since_binning_[i].setZero();
    }
  if (cells_->n_moved() * kMovedFractionForRebuild > positions_.size()) rebin();
}

// The end of a round: the solutions' touching pairs become links (a retreat first
// dissolves the bodies of its group), then the new overlaps form the next S; one inside a
// body dissolves it and takes its links along. Returns false when the round changed
// nothing that the next one could build on (no new link and no new pair: it would repeat).
template <int D>
bool TimeSteppingEngine<D>::end_round(const State<D>& s, const std::vector<CollisionGroup>& groups,
                                      const std::vector<GroupSolution<D>>& solutions,
                                      const std::vector<SpherePair>& overlaps) {
  const double eps_c = settings_.daha.eps_c;
  auto touching = [&](const SpherePair& p) {
    const double sigma = s.spheres.radius[p.i] + s.spheres.radius[p.j];
    return std::abs(s.box.separation(positions_[p.i], positions_[p.j]).norm() / sigma - 1.0) <= eps_c;
  };
  std::vector<SpherePair> next;
  for (std::size_t k = 0; k < groups.size(); ++k)
    if (solutions[k].dissolves_bodies)
      for (int body : groups[k].bodies) bodies_.dissolve(body);
  // Whether each contact touches, read from scattered spheres: on the threads when there
  // are many (10^5 and more in the first rounds of a run of 10^6); the links in order.
  std::vector<std::size_t> first_contact(solutions.size() + 1, 0);
  for (std::size_t k = 0; k < solutions.size(); ++k)
    first_contact[k + 1] = first_contact[k] + solutions[k].contacts.size();
  std::vector<char> touches(first_contact.back());
  const std::int64_t n_solutions = static_cast<std::int64_t>(solutions.size());
#pragma omp parallel for schedule(dynamic, 256) if (touches.size() >= kParallelLoopMin)
  for (std::int64_t k = 0; k < n_solutions; ++k)
    for (std::size_t m = 0; m < solutions[k].contacts.size(); ++m)
      touches[first_contact[k] + m] = touching(solutions[k].contacts[m]);
  bool progress = false;
  for (std::size_t k = 0; k < solutions.size(); ++k)
    for (std::size_t m = 0; m < solutions[k].contacts.size(); ++m) {
      if (!touches[first_contact[k] + m]) continue;
      const SpherePair& p = solutions[k].contacts[m];
      const int ci = s.spheres.cluster[p.i], cj = s.spheres.cluster[p.j];
      progress = progress || bodies_.body_of(ci) != bodies_.body_of(cj);
      bodies_.link(p, ci, cj);
    }
  S_.clear();
  for (const SpherePair& p : overlaps) {
    const int body = body_of_sphere(s, p.i);
    if (body == body_of_sphere(s, p.j))
      for (const SpherePair& l : bodies_.dissolve(body)) next.push_back(l);
    next.push_back(p);
  }
  for (const SpherePair& p : next) {
    const int bi = body_of_sphere(s, p.i), bj = body_of_sphere(s, p.j);
    if (bi == bj && rigid()) continue;  // a link of a body that was dissolved and formed again
    if (S_.add(p.i, p.j, bi, bj)) {
      S_.pair(static_cast<std::int32_t>(S_.pairs().size()) - 1).lambda = p.lambda;
      progress = true;
    }
  }
  return progress || S_.empty();
}

// When the loop gives up (out of rounds, a repeating round, a round that changes nothing)
// with pairs still overlapping: pairs touching within eps_c become links; the clusters of
// the deeper ones, and every cluster linked to them in this step, retreat together along
// their flights (place_at_contact of one group), and the spheres that retreat finds in
// their way join the group and the retreat is made again, until it leaves no overlap
// beyond eps_c. It ends: the group only grows, and a group of every cluster that moved in
// the step returns to the start of the step, where no two clusters overlapped. The pairs
// it leaves touching are links, so the clusters merge and the run goes on.
//
// Left apart, such an overlap would outlive the step: at N = 10^6 pairs overlapping by 0.8
// of a diameter were left after the third step, their groups came back at every later step,
// where neither a minimisation nor a retreat (which goes back at most to the start of the
// step) could separate them, and the run stopped making progress. Merged where they were
// (the rule before this one), they froze overlaps of up to 0.98 sigma into the aggregates.
template <int D>
void TimeSteppingEngine<D>::settle(const State<D>& s, const std::vector<SpherePair>& left) {
  const double eps_c = settings_.daha.eps_c;
  auto deep = [&](const SpherePair& p) {
    const double sigma = s.spheres.radius[p.i] + s.spheres.radius[p.j];
    return 1.0 - s.box.separation(positions_[p.i], positions_[p.j]).norm() / sigma > eps_c;
  };
  std::vector<std::int32_t> retreating;  // clusters, sorted
  for (const SpherePair& p : left)
    if (deep(p))
      for (int i : {p.i, p.j}) retreating.push_back(s.spheres.cluster[i]);
  sort_unique(retreating);
  std::vector<std::int32_t> group_clusters;  // sorted
  std::vector<int> settled;                  // spheres moved by the retreats
  std::vector<SpherePair> contacts;
  while (!retreating.empty()) {
    // Every cluster linked to a retreating one in this step retreats with it: where their
    // flights started, they were free of each other.
    for (int c : retreating) {
      const int body = bodies_.body_of(c);
      for (int k : bodies_.clusters_of(body)) group_clusters.push_back(k);
      bodies_.dissolve(body);
    }
    sort_unique(group_clusters);
    const GroupSolution<D> solution = place_at_contact(context(s), CollisionGroup{group_clusters, {}});
    std::vector<int> moved(solution.spheres.begin(), solution.spheres.end());
    apply(s, solution, settled);
    contacts = solution.contacts;
    // Only what moved now can overlap anything new: nothing outside the group moves here.
    retreating = clusters_overlapping_outside(s, moved, group_clusters);
  }
  moved_in_step_.insert(moved_in_step_.end(), settled.begin(), settled.end());
  for (const SpherePair& p : contacts) bodies_.link(p, s.spheres.cluster[p.i], s.spheres.cluster[p.j]);
  // The pairs that were only touching are links, unless one of their clusters retreated.
  auto retreated = [&](int i) {
    return std::binary_search(group_clusters.begin(), group_clusters.end(), s.spheres.cluster[i]);
  };
  for (const SpherePair& p : left)
    if (!deep(p) && !retreated(p.i) && !retreated(p.j))
      bodies_.link(p, s.spheres.cluster[p.i], s.spheres.cluster[p.j]);
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
  // read at N = 10^6) and a square root taken; the same pairs reach f.
  const double far2 = beyond_squared(2.0 * s.max_radius());
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
    cells_->for_each_near(positions_[i], visit);
  }
}

// The cells where apply() put spheres beyond the near list's half skin, and the cells
// next to them (touching spheres are in neighbouring cells: a cell is at least a contact
// distance wide).
template <int D>
void TimeSteppingEngine<D>::mark_spheres_beyond_skin() {
  const GridGeometry<D>& grid = cells_->sorted().grid();
  for (std::vector<std::int32_t>& found : beyond_found_) {
    for (std::int32_t cell : found) {
      if (beyond_mark_[cell] & kHoldsBeyond) continue;
      grid.for_each_cell_near(grid.centre(cell), [&](std::int64_t c) { beyond_mark_[c] |= kBesideBeyond; });
      beyond_mark_[cell] |= kHoldsBeyond;
      beyond_cells_.push_back(cell);
    }
    found.clear();
  }
}

// Whether the contact passes can skip sphere i (rigid model: only other clusters count).
// A sphere in no listed near pair is farther than its contact distance from every sphere
// of another cluster, as long as both clusters are within the near list's half skin of
// where their pairs were listed (NearPairs::listed). So it is skipped when its cluster is,
// and no sphere moved beyond the half skin in this step is in a cell next to its own.
// Late in a run a fragment that hits the giant moves it by a tiny shift: each of the
// giant's spheres is a lookup instead of a cell query. Earlier, at N = 10^6, a retreat
// takes a cluster back along a flight of up to 8 diameters, far beyond the skin, and the
// spheres that later rounds of the step move elsewhere in the box are skipped as well.
template <int D>
bool TimeSteppingEngine<D>::needs_no_contact_query(const State<D>& s, int i) const {
  if (!rigid() || near_.listed(i)) return false;
  if (near_list_complete_) return true;
  return !beyond_mark_[cells_->sorted().grid().cell_index(positions_[i])] && !beyond_half_skin(s, i);
}

template <int D>
void TimeSteppingEngine<D>::forget_spheres_beyond_skin() {
  const GridGeometry<D>& grid = cells_->sorted().grid();
  for (std::int32_t cell : beyond_cells_)
    grid.for_each_cell_near(grid.centre(cell), [&](std::int64_t c) { beyond_mark_[c] = 0; });
  beyond_cells_.clear();
}

// A pass over the spheres moved since the previous one (`moved`, sorted, each once: every
// sphere apply() moved since), calling f as for_each_contact does, and keeping what it sees
// for residual_overlap: the overlaps that could raise max_residual_overlap.
template <int D>
template <class F>
void TimeSteppingEngine<D>::contact_pass(const State<D>& s, const std::vector<int>& moved, F&& f) {
  forget_outdated_sightings();
  const std::int32_t pass = pass_++;
  const double largest_so_far = counters_.max_residual_overlap;
  fit_to_team(sightings_);
  for_each_contact(s, moved, [&](int i, int j, double d, double sigma) {
    const double overlap = 1.0 - d / sigma;
    if (overlap > largest_so_far) sightings_[thread_index()].push_back({i, j, pass, overlap});
    f(i, j, d, sigma);
  });
}

// A sighting is out of date once a later pass moved one of its spheres (below). The first
// steps of a large run see millions of overlaps in many rounds, most soon out of date:
// they are dropped whenever the records have doubled since the last time.
template <int D>
void TimeSteppingEngine<D>::forget_outdated_sightings() {
  std::size_t total = 0;
  for (const auto& seen : sightings_) total += seen.size();
  if (total <= forget_at_) return;
  total = 0;
  for (auto& seen : sightings_) {
    std::erase_if(seen, [&](const Sighting& k) { return k.pass < std::max(last_pass_[k.i], last_pass_[k.j]); });
    total += seen.size();
  }
  forget_at_ = std::max(2 * total, kSightingsKept);
}

// The largest relative overlap left at the end of the step between a sphere the step moved
// and any other, from what the contact passes saw, without a pass of its own (which was a
// tenth of a run of 10^6). The pass that follows a sphere's last move sees every pair of
// it at its final distance; a pair seen earlier, when a later pass moved one of its
// spheres again, is out of date (and may have come apart since, unseen): a sighting
// counts only if it is from the last pass that moved either of its spheres. Clears the
// step's records.
template <int D>
double TimeSteppingEngine<D>::residual_overlap() {
  double largest = 0.0;
  for (std::vector<Sighting>& seen : sightings_) {
    for (const Sighting& k : seen)
      if (k.pass == std::max(last_pass_[k.i], last_pass_[k.j])) largest = std::max(largest, k.overlap);
    // The first steps of a large run see millions of overlaps, the later ones a few.
    if (seen.capacity() > kSightingsKept) std::vector<Sighting>().swap(seen);
    seen.clear();
  }
  for (int i : moved_in_step_) last_pass_[i] = -1;
  pass_ = 0;
  forget_at_ = kSightingsKept;
  return largest;
}

// (3.2): the pairs brought to contact (phi >= 0) by this round, sorted. A pair of S, or
// one a solution left touching, is settled while it touches (within eps_c); pushed deeper
// (by another group's solution, or left so by a repair) it counts again. In the per-sphere
// models an old link counts again when it is squeezed beyond eps_c, so that its group is
// solved again.
template <int D>
std::vector<SpherePair> TimeSteppingEngine<D>::new_overlaps(const State<D>& s, std::vector<int>& moved) {
  sort_unique_ids(moved, s.n_spheres());
  std::vector<std::vector<SpherePair>> found(max_threads());
  const double eps_c = settings_.daha.eps_c;
  contact_pass(s, moved, [&](int i, int j, double d, double sigma) {
    const bool settled = S_.contains(i, j) || round_contacts_.find(i, j) != PairIndex::kAbsent ||
                         (!rigid() && links_.linked(i, j));
    if (settled && 1.0 - d / sigma <= eps_c) return;
    if (rigid() && body_of_sphere(s, i) == body_of_sphere(s, j) && 1.0 - d / sigma <= eps_c) return;
    found[thread_index()].push_back({std::min(i, j), std::max(i, j), 0.0});
  });
  std::vector<SpherePair> pairs;
  for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  sort_unique(pairs, pair_less<SpherePair>);  // found from both ends when both moved
  return pairs;
}

// The per-sphere models: each moved sphere is displaced in its cluster.
template <int D>
void TimeSteppingEngine<D>::commit_moves(State<D>& s, std::vector<std::int32_t>& moved_clusters) {
  for (const int i : moved_in_step_) {
    const int c = s.spheres.cluster[i];
    near_.shifted(c, step_shift_[i].norm());
    if (committed_moves_[c] == 0.0) moved_clusters.push_back(c);
    committed_moves_[c] = std::max(committed_moves_[c], moved_since_binning_[i].norm());
    moved_since_binning_[i].setZero();
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
// test for its first member (a scattered read per sphere: with the per-sphere loop on one
// thread, this was the largest serial part of a step early in a run of 10^6).
template <int D>
void TimeSteppingEngine<D>::commit_rigid_moves(State<D>& s, std::vector<std::int32_t>& moved_clusters) {
  const std::int64_t n = static_cast<std::int64_t>(moved_in_step_.size());
  std::vector<double> drift(moved_in_step_.size(), -1.0);  // -1: not its cluster's first member
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
  for (std::int64_t k = 0; k < n; ++k) {
    const int i = moved_in_step_[k];
    const std::vector<int>& members = s.clusters[s.spheres.cluster[i]].members;
    if (members.front() != i) continue;
    double largest = 0.0;
    for_each_prefetched(
        members, [&](int j) { largest = std::max(largest, moved_since_binning_[j].norm()); }, moved_since_binning_);
    drift[k] = largest;
  }
#pragma omp parallel for schedule(static) if (n >= kParallelLoopMin)
  for (std::int64_t k = 0; k < n; ++k) moved_since_binning_[moved_in_step_[k]].setZero();
  for (std::int64_t k = 0; k < n; ++k) {
    if (drift[k] < 0.0) continue;
    const int i = moved_in_step_[k];
    const int c = s.spheres.cluster[i];
    near_.shifted(c, step_shift_[i].norm());
    if (committed_moves_[c] == 0.0) moved_clusters.push_back(c);
    committed_moves_[c] = std::max(committed_moves_[c], drift[k]);
    s.translate(c, step_shift_[i], s.time);
  }
}

// Step 3: the state's clusters are moved to their minimised positions, and the links of
// the step merge them, pair by pair, with the mass-weighted velocity of rule (2.9).
// Returns the merges.
template <int D>
int TimeSteppingEngine<D>::commit(State<D>& s) {
  sort_unique_ids(moved_in_step_, s.n_spheres());
  // The step's moves since binning join each cluster's drift, its spheres' largest (a
  // cluster may be listed more than once while its largest is zero, which adds nothing).
  std::vector<std::int32_t> moved_clusters;
  if (rigid()) commit_rigid_moves(s, moved_clusters);
  else commit_moves(s, moved_clusters);
  near_.flush_shifts();
  for (std::int32_t c : moved_clusters) {
    binned_drift_[c] += committed_moves_[c];
    committed_moves_[c] = 0.0;
  }
  int merges = 0;
  for (const SpherePair& p : bodies_.all_links()) {
    if (!rigid()) links_.add(p.i, p.j, p.lambda);
    const int ci = s.spheres.cluster[p.i], cj = s.spheres.cluster[p.j];
    if (ci == cj) continue;
    ++counters_.collisions;
    const int into = s.merge(p.i, p.j, s.time);
    near_.merged(ci, cj, into);
    binned_drift_[into] = std::max(binned_drift_[ci], binned_drift_[cj]);
    ++merges;
  }
  counters_.merges += merges;
  for (int i : moved_in_step_) step_shift_[i].setZero();
  moved_in_step_.clear();
  bodies_.clear();
  // The minimisations do not push clusters through walls (their bounds), but a cluster as
  // wide as the box can end a step a little through one (a retreat takes it back along a
  // flight that began there): it is moved back at the start of the next step, before the
  // overlap detection (moving it now could create overlaps).
  return merges;
}

}  // namespace

template <int D>
std::unique_ptr<Engine<D>> make_time_stepping_engine(const TimeSteppingSettings& settings, DahaProblemSink<D>* sink) {
  return std::make_unique<TimeSteppingEngine<D>>(settings, sink);
}

template std::unique_ptr<Engine<2>> make_time_stepping_engine<2>(const TimeSteppingSettings&, DahaProblemSink<2>*);
template std::unique_ptr<Engine<3>> make_time_stepping_engine<3>(const TimeSteppingSettings&, DahaProblemSink<3>*);

}  // namespace ballagg
