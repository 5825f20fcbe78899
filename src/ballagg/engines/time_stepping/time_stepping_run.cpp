// The run around the steps of the time-stepping engine (ts_engine.hpp): the stop criteria,
// checkpoints, and the steps of zero length that bring the final state inside the walls.
#include <algorithm>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/engines/time_stepping/ts_engine.hpp"
#include "ballagg/spatial/walls.hpp"

namespace ballagg {
namespace {

// Steps of zero length at the end of a run that move clusters the last minimisation pushed
// through a wall back inside, and resolve the overlaps this creates.
constexpr int kFinalWallSteps = 8;

}  // namespace

template <int D>
RunResult TimeSteppingEngine<D>::run(State<D>& s, const StopCriteria& stop, RunObserver<D>& observer) {
  RunGuard own_guard(stop.wall_seconds);
  RunGuard& guard = stop.guard != nullptr ? *stop.guard : own_guard;
  guard_ = &guard;
  // The team of the parallel regions, measured between steps and between the stages of a
  // step (a step of a large run lasts long enough for the machine's load to change).
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
      observer.on_checkpoint_stream(s, counters_, [&](ByteWriter& w) { save(w); });
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
  result.engine_counts = counters_.report(!rigid(), paper());
  result.wall_seconds = guard.elapsed();
  guard_ = nullptr;
  observer.on_finish(s, result);
  return result;
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
  cells_.reset(s);
  step_shift_.assign(n, Vec<D>::Zero());
  sightings_.reset(n);
  beyond_skin_.reset(cells_.list().sorted().grid().n_cells());
  near_ = NearPairs<D>(n_cluster_ids, cells_.slack());
  S_.reset(n_cluster_ids);
  bodies_.reset(n_cluster_ids);
  if (!rigid()) links_ = AdhesiveLinks(n);
}

template <int D>
void TimeSteppingEngine<D>::save(ByteWriter& w) const {
  counters_.save(w, paper());
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
}

template <int D>
void TimeSteppingEngine<D>::resume_from(State<D>& s, std::string_view saved) {
  ByteReader r(saved, "checkpoint of the ts engine");
  prepare(s);
  counters_.restore(r, paper());
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

#define BALLAGG_TS_RUN(D)                                                                         \
  template RunResult TimeSteppingEngine<D>::run(State<D>&, const StopCriteria&, RunObserver<D>&); \
  template void TimeSteppingEngine<D>::resume_from(State<D>&, std::string_view);                  \
  template void TimeSteppingEngine<D>::save(ByteWriter&) const;                                       \
  template void TimeSteppingEngine<D>::prepare(const State<D>&);                                  \
  template bool TimeSteppingEngine<D>::outside_walls(const State<D>&) const;
BALLAGG_TS_RUN(2)
BALLAGG_TS_RUN(3)
#undef BALLAGG_TS_RUN

}  // namespace ballagg
