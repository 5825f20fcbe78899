// One step of the time-stepping method, paper §3 (docs/time_stepping.md), from t^{n-1}
// to t^n = t^{n-1} + Delta t^n:
//
//   1.     free advection, X^n = X^{n-1} + Delta t^n V^{n-1}, and the walls     advect
//   2a.    S^{n,0}: the pairs of spheres of different clusters in contact        detect_overlaps
//   2b-2e. the loop (3.1)-(3.2): X^{n,q} minimises W over S^{n,q-1} under phi <= 0
//          (the DAHA (3.20)-(3.24), daha.cpp, one problem per group of S,
//          minimisation_problem.cpp); S^{n,q} adds the pairs that came into contact;
//          until S^{n,q} = S^{n,q-1}                                             resolve
//   3.     the new clusters, with the mass-weighted velocity of rule (2.9)      commit
//
// A group the DAHA does not solve goes to the fall-back (retreat.hpp, flight_sweep.hpp);
// with ts.method = "paper" its iterate is accepted and counted, as the paper's loop would.
// The class and the files of its other parts are in ts_engine.hpp.
#include "ballagg/engines/time_stepping/time_stepping_engine.hpp"

#include <algorithm>
#include <bit>

#include "ballagg/core/finite_state.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/engines/time_stepping/flight_sweep.hpp"
#include "ballagg/engines/time_stepping/repair_waves.hpp"
#include "ballagg/engines/time_stepping/retreat.hpp"
#include "ballagg/engines/time_stepping/ts_engine.hpp"
#include "ballagg/spatial/walls.hpp"

namespace ballagg {
namespace {

// Pairs in one round from which its groups are solved on several threads (starting them
// costs more than solving a few small groups).
constexpr std::size_t kParallelPairs = 2000;

// Groups in one wave of fall-backs from which they are repaired on several threads (a
// large repair that runs alone shares its own searches among the threads).
constexpr std::int64_t kParallelRepairs = 2;

}  // namespace

// One step to time t (t = s.time: walls and overlaps only). The observers' output before
// it may be cut short by a signal (RunGuard): the step is then not taken, and the
// checkpoint written next resumes where the output stopped. Cut short otherwise (the
// wall-clock limit, an output cap), the step is taken and the run ends after it, without
// the output that had no time to be written.
template <int D>
void TimeSteppingEngine<D>::step(State<D>& s, double t, RunObserver<D>& observer) {
  observer.before_event(s, t);
  if (guard_->cause() == StopCause::signal) return;
  advect(s, t - s.time);         // 1.
  cells_.defer_positions(s);
  detect_overlaps(s);            // 2a.
  poll_team();
  resolve(s);                    // 2b-2e.
  EventRecord record;
  record.merges = commit(s);     // 3.
  ++counters_.steps;
  ++counters_.events;
  record.time = s.time;
  record.kind = EventKind::time_step;
  observer.after_event(s, record, counters_);
}

// Step 1: free flight (positions are lazy: O(1) per cluster), then walls. Records each
// cluster's displacement (walls included), the way back for a retreat.
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
    cells_.drifted(c, flight_[c].norm());
  }
}

// Step 2a: S starts as the pairs of spheres of different clusters that overlap or touch
// (phi >= 0) after the free flight, found among the near pairs (near_pairs.hpp). A scan
// of the whole box reads the cell list in slot order: it is built afresh. A partial
// refresh queries it as it is binned (StepCells::for_queries).
template <int D>
void TimeSteppingEngine<D>::detect_overlaps(const State<D>& s) {
  const NearPairCells<D> cells{[&]() -> const SortedCellList<D>& {
                                 cells_.rebin();
                                 return cells_.list().sorted();
                               },
                               [&](std::size_t queries) { return cells_.for_queries(s, queries, near_.skin()); }};
  const auto need = [this](const std::vector<std::int32_t>& spheres) { cells_.materialise(spheres); };
  const std::vector<SpherePair> touching = near_.contacts(s, positions_, cells, need);
  S_.add_all(touching, s.spheres.cluster);
  near_list_complete_ = true;  // every cluster is within skin / 2 of its listing now
  beyond_skin_.clear(cells_.list().sorted().grid());
}

// Steps 2b-2e, the loop (3.1)-(3.2). Each round minimises every group of S (the bodies
// joined by S), links the pairs the solutions leave touching (their bodies move as one
// from then on), and takes as the next S the pairs the minimisation brought into contact.
// An overlap inside a body dissolves it: its links rejoin S with that overlap, and its
// clusters are solved again separately. The loop ends when a round brings no new contact;
// max_link_rounds bounds it. With ts.method = "paper" every solution is applied, converged
// or not (end_of_loop says what becomes of the pairs left when the loop is cut short).
template <int D>
void TimeSteppingEngine<D>::resolve(const State<D>& s) {
  if (S_.empty()) return;
  cells_.binned(s);
  std::vector<int> moved;
  std::vector<std::uint64_t> earlier_rounds;  // their signatures
  for (int round = 1;; ++round) {
    const std::vector<CollisionGroup> groups = S_.take_changed_groups();
    if (groups.empty()) break;  // S^{n,q} = S^{n,q-1}
    poll_team();
    if (round > 1) ++counters_.link_rounds;
    const bool out_of_rounds = round_is_last(round, earlier_rounds);
    // (3.1), group by group; what the DAHA does not solve is repaired by the fall-back.
    std::vector<GroupSolution<D>> solutions = minimise_groups(s, groups, out_of_rounds);
    moved.clear();
    std::vector<const GroupSolution<D>*> solved;
    for (const GroupSolution<D>& solution : solutions) {
      if (paper() && !solution.result.converged) ++counters_.minimisations_unconverged;
      if (solution.result.converged || paper()) solved.push_back(&solution);
    }
    apply(s, solved, moved);
    if (!paper()) repair_unsolved(s, groups, solutions, moved);
    moved_in_step_.insert(moved_in_step_.end(), moved.begin(), moved.end());
    if (out_of_rounds) {
      end_round(s, groups, solutions, {});
      S_.clear();
      end_of_loop(s, new_overlaps(s, moved));
      break;
    }
    // (3.2): the touching pairs become links, the new contacts the next S.
    round_contacts_.clear();
    for (const GroupSolution<D>& g : solutions)
      for (const SpherePair& c : g.contacts) round_contacts_.insert(c.i, c.j, 0);
    if (!end_round(s, groups, solutions, new_overlaps(s, moved))) {
      ++counters_.rounds_exhausted;  // stalled: what is left overlapping is settled
      const std::vector<SpherePair> left = S_.pairs();
      S_.clear();
      end_of_loop(s, left);
      break;
    }
  }
  counters_.max_residual_overlap = std::max(counters_.max_residual_overlap, residual_overlap());
}

// The pairs still in contact when the loop is cut short. Ours: settled (settle.cpp). The
// paper's method has no such step: the pairs are in S^{n,q} (3.2), so they are links and
// their clusters merge where they are; the overlaps they keep are counted in
// max_residual_overlap.
template <int D>
void TimeSteppingEngine<D>::end_of_loop(const State<D>& s, const std::vector<SpherePair>& left) {
  if (!paper()) {
    settle(s, left);
    return;
  }
  for (const SpherePair& p : left) bodies_.link(p, s.spheres.cluster[p.i], s.spheres.cluster[p.j]);
}

// Whether this round is the loop's last: max_link_rounds reached, a round with the adhesive
// set of an earlier round of this step (a cycle that would repeat the rounds since until
// max_link_rounds), or a step that must end (RunGuard::step_must_end: the wall-clock
// limit, or a signal that has waited). Its groups then all go to the fall-back.
template <int D>
bool TimeSteppingEngine<D>::round_is_last(int round, std::vector<std::uint64_t>& earlier_rounds) {
  const std::uint64_t signature = round_signature();
  const bool repeats = std::find(earlier_rounds.begin(), earlier_rounds.end(), signature) != earlier_rounds.end();
  earlier_rounds.push_back(signature);
  const bool out_of_rounds =
      round >= settings_.max_link_rounds || repeats || (guard_ != nullptr && guard_->step_must_end());
  if (out_of_rounds) ++counters_.rounds_exhausted;
  return out_of_rounds;
}

// (3.1) for every group of the round at once, on the threads when there is enough work
// (none in the loop's last round, whose groups go to the fall-back; with ts.method =
// "paper", which has none, the last round is solved like the others). A group
// beyond_minimisation is left unsolved.
template <int D>
std::vector<GroupSolution<D>> TimeSteppingEngine<D>::minimise_groups(const State<D>& s,
                                                                    const std::vector<CollisionGroup>& groups,
                                                                    bool out_of_rounds) {
  const StepView<D> ctx = view(s);
  std::vector<GroupSolution<D>> solutions(groups.size());
  if (out_of_rounds && !paper()) return solutions;
  std::size_t work = 0;
  for (const CollisionGroup& g : groups) work += g.pairs.size();
#pragma omp parallel for schedule(dynamic) if (groups.size() > 1 && work >= kParallelPairs)
  for (std::size_t k = 0; k < groups.size(); ++k)
    if (!beyond_minimisation(s, groups[k])) solutions[k] = solve_group(ctx, groups[k]);
  return solutions;
}

// The groups the minimisation did not solve are repaired one after the other, each seeing
// where everything else has gone, in the order of repair_waves.hpp; those that cannot see
// each other at once, wave by wave (the same answers).
template <int D>
void TimeSteppingEngine<D>::repair_unsolved(const State<D>& s, const std::vector<CollisionGroup>& groups,
                                            std::vector<GroupSolution<D>>& solutions, std::vector<int>& moved) {
  const StepView<D> ctx = view(s);
  std::vector<std::size_t> failed;
  for (std::size_t k = 0; k < groups.size(); ++k) {
    if (solutions[k].result.converged) continue;
    failed.push_back(k);
    solutions[k].release_moves();
  }
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
// another, and no nearby configuration says from which side it came; off by default).
// Such minimisations seldom converge and would cost most of the DAHA's work. Rigid model
// only: in the per-sphere models S also holds the clusters' own squeezed links, which a
// minimisation must see.
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

// The end of a round, (3.2): the solutions' touching pairs become links (a retreat first
// dissolves the bodies of its group), then the new overlaps form the next S; one inside a
// body dissolves it and takes its links along. Returns false when the round changed
// nothing that the next one could build on (no new link and no new pair: it would repeat).
template <int D>
bool TimeSteppingEngine<D>::end_round(const State<D>& s, const std::vector<CollisionGroup>& groups,
                                      const std::vector<GroupSolution<D>>& solutions,
                                      const std::vector<SpherePair>& overlaps) {
  std::vector<SpherePair> next;
  for (std::size_t k = 0; k < groups.size(); ++k)
    if (solutions[k].dissolves_bodies)
      for (int body : groups[k].bodies) bodies_.dissolve(body);
  bool progress = link_touching_contacts(s, solutions);
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

// Links the solutions' contacts that touch (within eps_c), in solution order; whether each
// touches is read from scattered spheres, on the threads when there are many. Returns
// whether a link joined two bodies. With ts.method = "paper" every contact is a link,
// touching or not: they are S^{n,q} (3.2), which makes the clusters.
template <int D>
bool TimeSteppingEngine<D>::link_touching_contacts(const State<D>& s, const std::vector<GroupSolution<D>>& solutions) {
  const double eps_c = settings_.daha.eps_c;
  auto touching = [&](const SpherePair& p) {
    const double sigma = s.spheres.radius[p.i] + s.spheres.radius[p.j];
    return std::abs(s.box.separation(positions_[p.i], positions_[p.j]).norm() / sigma - 1.0) <= eps_c;
  };
  std::vector<std::size_t> first_contact(solutions.size() + 1, 0);
  for (std::size_t k = 0; k < solutions.size(); ++k)
    first_contact[k + 1] = first_contact[k] + solutions[k].contacts.size();
  std::vector<char> touches(first_contact.back());
  const std::int64_t n_solutions = static_cast<std::int64_t>(solutions.size());
#pragma omp parallel for schedule(dynamic, 256) if (touches.size() >= kParallelLoopMin)
  for (std::int64_t k = 0; k < n_solutions; ++k)
    for (std::size_t m = 0; m < solutions[k].contacts.size(); ++m)
      touches[first_contact[k] + m] = paper() || touching(solutions[k].contacts[m]);
  bool progress = false;
  for (std::size_t k = 0; k < solutions.size(); ++k)
    for (std::size_t m = 0; m < solutions[k].contacts.size(); ++m) {
      if (!touches[first_contact[k] + m]) continue;
      const SpherePair& p = solutions[k].contacts[m];
      const int ci = s.spheres.cluster[p.i], cj = s.spheres.cluster[p.j];
      progress = progress || bodies_.body_of(ci) != bodies_.body_of(cj);
      bodies_.link(p, ci, cj);
    }
  return progress;
}

// Step 3: the state's clusters are moved to their minimised positions, and the links of
// the step merge them, pair by pair, with the mass-weighted velocity of rule (2.9).
// Returns the merges. The minimisations do not push clusters through walls (their
// bounds), but a cluster as wide as the box can end a step a little through one (a
// retreat takes it back along a flight that began there): it is moved back at the start
// of the next step, before the overlap detection (moving it now could create overlaps).
template <int D>
int TimeSteppingEngine<D>::commit(State<D>& s) {
  sort_unique_ids(moved_in_step_, s.n_spheres());
  // The step's moves since binning join each cluster's drift, its spheres' largest (a
  // cluster may be listed more than once while its largest is zero, which adds nothing).
  std::vector<std::int32_t> moved_clusters;
  if (rigid()) commit_rigid_moves(s, moved_clusters);
  else commit_moves(s, moved_clusters);
  near_.flush_shifts();
  cells_.commit_drifts(moved_clusters);
  int merges = 0;
  for (const SpherePair& p : bodies_.all_links()) {
    if (!rigid()) links_.add(p.i, p.j, p.lambda);
    const int ci = s.spheres.cluster[p.i], cj = s.spheres.cluster[p.j];
    if (ci == cj) continue;
    ++counters_.collisions;
    const int into = s.merge(p.i, p.j, s.time);
    near_.merged(ci, cj, into);
    cells_.merged(ci, cj, into);
    ++merges;
  }
  counters_.merges += merges;
  // The guard against a numerical failure (core/finite_state.hpp), on what the step moved.
  throw_if_not_finite(s, name(), first_non_finite<D>(s, moved_in_step_));
  for (int i : moved_in_step_) step_shift_[i].setZero();
  moved_in_step_.clear();
  bodies_.clear();
  return merges;
}

template void TimeSteppingEngine<2>::step(State<2>&, double, RunObserver<2>&);
template void TimeSteppingEngine<3>::step(State<3>&, double, RunObserver<3>&);

template <int D>
std::unique_ptr<Engine<D>> make_time_stepping_engine(const TimeSteppingSettings& settings, DahaProblemSink<D>* sink) {
  return std::make_unique<TimeSteppingEngine<D>>(settings, sink);
}

template std::unique_ptr<Engine<2>> make_time_stepping_engine<2>(const TimeSteppingSettings&, DahaProblemSink<2>*);
template std::unique_ptr<Engine<3>> make_time_stepping_engine<3>(const TimeSteppingSettings&, DahaProblemSink<3>*);

}  // namespace ballagg
