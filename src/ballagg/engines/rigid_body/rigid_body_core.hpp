#pragma once
// The core of the rigid-body engine (rigid_body_engine.cpp describes the engine): the bodies,
// their neighbour lists and predictions, and the handlers of its events. Its members are
// defined by concept: detection in rigid_body_lists.cpp (the lists) and
// rigid_body_prediction.cpp (contact times and searches), rigid_body_walls.cpp,
// rigid_body_collisions.cpp, rigid_body_checkpoint.cpp; each is instantiated there for D = 2, 3.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/collision/resolve.hpp"
#include "ballagg/core/input_error.hpp"
#include "ballagg/core/state.hpp"
#include "ballagg/engines/engine.hpp"
#include "ballagg/engines/event_driven/calendar_dispatch.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/engines/event_driven/neighbor_keeper.hpp"
#include "ballagg/engines/rigid_body/contact_search.hpp"
#include "ballagg/engines/rigid_body/rigid_bodies.hpp"
#include "ballagg/engines/rigid_body/rigid_body_counters.hpp"
#include "ballagg/engines/rigid_body/rigid_body_engine.hpp"
#include "ballagg/engines/rigid_body/rotation_drift.hpp"
#include "ballagg/spatial/cell_grid.hpp"
#include "ballagg/spatial/neighbor_lists.hpp"

namespace ballagg {

template <int D>
class RigidBodyCore : public CalendarDispatch<RigidBodyCore<D>> {
  friend class CalendarDispatch<RigidBodyCore<D>>;
  using CalendarDispatch<RigidBodyCore<D>>::calendar_;
  using Pose = typename RigidBodies<D>::Pose;

 public:
  using Settings = RigidBodySettings;
  RigidBodyCore(State<D>& state, const RigidBodySettings& settings)
      : s_(state), settings_(settings),
        keeper_(RotationDrift<D>(state, bodies_), fitted_skin(state, settings.skin.value_or(0.0), rigid_body_skin(state),
                                                              SkinLimitRounding::multiply_first)) {
    keep_what_the_law_reads(s_, settings_.collision);
    if (settings_.law.coagulation == Coagulation::sphere) {
      for (int c : s_.alive_clusters())
        if (s_.clusters[c].size() > 1)
          throw InputError(fmt::format("collision.coagulation = \"sphere\" merges single spheres, but the initial "
                                       "state glues {} spheres into one cluster", s_.clusters[c].size()));
    }
    s_.reserve_clusters(s_.n_spheres());
    bodies_.build(s_);
    const int m = static_cast<int>(s_.clusters.size());
    serial_.resize(m);
    partner_.assign(m, -1);
    for (int c = 0; c < m; ++c) {
      serial_[c] = next_serial_++;
      if (!s_.clusters[c].alive()) empty_.push_back(c);
    }
    std::reverse(empty_.begin(), empty_.end());  // lowest ids taken first (from the back)
    merged_sphere_.assign(s_.n_spheres(), 0);
    for (int c : s_.alive_clusters())
      if (s_.clusters[c].size() == 1) free_mass_ += s_.clusters[c].mass;
    total_mass_ = s_.total_mass();
    build_spatial();
    check_span(-1);
  }

  // Restores what save() wrote for this state (a checkpoint), nothing computed again: the
  // run goes on with the very bodies, lists and events the saved one had.
  RigidBodyCore(State<D>& state, const RigidBodySettings& settings, std::string_view saved);

  // Everything the engine carries from one event to the next, the state aside; and the
  // state's spins, which only this engine writes. The state itself is saved as it is: its
  // sphere offsets are those last written (write_state), and the run goes on from the
  // bodies saved here, so the resumed state stays, field by field, the uninterrupted one.
  void save(ByteWriter& w) const;

  RunResult run(State<D>& state, const StopCriteria& stop, RunObserver<D>& observer);

  RigidBodyCounters& counters() { return count_; }
  EventLoopState& loop() { return loop_; }
  // True once, for a core restored from a checkpoint: its state is the saved one as it
  // was, and must not be written anew at the start.
  bool take_resumed() { return std::exchange(resumed_, false); }

  std::optional<StopReason> stop_reason() const {
    if (spans_box_) return StopReason::body_spans_box;
    if (aggregated_target_ <= 1.0 && 1.0 - free_mass_ / total_mass_ >= aggregated_target_) return StopReason::aggregated;
    return std::nullopt;
  }
  void set_aggregated_target(double f) { aggregated_target_ = f; }

  // Writes every body's sphere offsets and spin at time t into the state (observers,
  // the end of the run).
  void write_state(double t) {
    for (int c : s_.alive_clusters()) bodies_.write_offsets(s_, c, t);
  }

 private:
  bool valid(const Event& e) const {
    switch (e.kind) {
      case EventKind::collision:
        return e.a < s_.n_spheres() && e.b < s_.n_spheres() && cluster_of(e.a).stamp == e.stamp_a &&
               cluster_of(e.b).stamp == e.stamp_b;
      case EventKind::wall: return e.a < s_.n_spheres() && cluster_of(e.a).stamp == e.stamp_a;
      case EventKind::contact_search:
        return s_.clusters[e.a].stamp == e.stamp_a && (e.b < 0 || s_.clusters[e.b].stamp == e.stamp_b);
      default: return s_.clusters[e.a].stamp == e.stamp_a;
    }
  }

  const Cluster<D>& cluster_of(int i) const { return s_.clusters[s_.spheres.cluster[i]]; }
  int body_of(int i) const { return s_.spheres.cluster[i]; }

  // ---- where things are -------------------------------------------------------------------

  // The pose of body c at time t, computed once per (body, time).
  const Pose& pose(int c, double t) {
    if (pose_time_[c] != t) {
      pose_[c] = bodies_.pose(c, t);
      pose_time_[c] = t;
      ++count_.pose_evaluations;
    }
    return pose_[c];
  }
  void forget_pose(int c) { pose_time_[c] = std::numeric_limits<double>::quiet_NaN(); }

  // Sphere i relative to its body's centre of mass at time t.
  Vec<D> offset(int i, double t) {
    const int c = body_of(i);
    if (s_.clusters[c].size() == 1) return Vec<D>::Zero();
    return bodies_.offset(i, c, pose(c, t));
  }
  Vec<D> unwrapped_position(int i, double t) { return s_.origin(body_of(i), t) + offset(i, t); }

  // ---- neighbour lists ----------------------------------------------------------------------

  double spin_bound(int c) const { return keeper_.bound().spin_bound(c); }

  // Calls found(j) for every foreign sphere j whose bin is within sigma + skin of sphere
  // i's bin, for which wanted(j) holds (engines/event_driven/neighbor_keeper.hpp).
  template <class Wanted, class Found>
  void for_each_foreign_near(int i, Wanted&& wanted, Found&& found) {
    ballagg::for_each_foreign_near(
        *grid_, s_, keeper_.skin(), body_of(i), grid_->binned(i), s_.spheres.radius[i], wanted,
        [&](int j) { return s_.spheres.radius[j]; }, found);
  }
  // Whether the pair (i, j) belongs in the lists: bins closer than sigma + skin. Bins,
  // not present places: a sphere of a spinning aggregate is not located (that would cost
  // an orientation), and every sphere stays within its body's drift of its bin.
  bool bins_within_reach(int i, int j) const {
    return ballagg::bins_within_reach(s_.box, grid_->binned(i), grid_->binned(j), s_.spheres.radius[i],
                                      s_.spheres.radius[j], keeper_.skin());
  }

  // Grid, lists, drifts and every prediction from scratch (start, and when coalescence
  // grows a sphere beyond the radius the grid was built for).
  void build_spatial();

  // The largest sphere radius the grid's cells are sized for. Coalescence grows spheres:
  // the grid is then sized for the next power of two of the largest radius, so that it is
  // built again only when that radius doubles (a function of the state alone, so a
  // checkpoint restores the very grid).
  double binned_radius() const {
    if (settings_.law.coagulation != Coagulation::sphere) return s_.max_radius();
    return std::exp2(std::ceil(std::log2(s_.max_radius())));
  }

  // The cells for grid_radius_ and the skin, at most settings_.cells_per_sphere per sphere.
  GridGeometry<D> grid_geometry() const {
    return {s_.box, binning_cell_size(grid_radius_, keeper_.skin()), s_.n_spheres(), settings_.cells_per_sphere};
  }

  // Drops the pairs of sphere i whose bins are out of reach. Removal swaps the last
  // partner into the hole, so walking the list from its end visits every entry once.
  void drop_out_of_reach(int i);

  EventRecord rebuild(int c, double t);

  // ---- predictions --------------------------------------------------------------------------

  // Files the list rebuild, wall contacts and contacts with every listed partner body of
  // body c, replacing everything filed under c before.
  void predict(int c, bool skip_lower_bodies = false, int skip_body = -1);

  // Predictions of body c with each partner body of pairs_ (sorted by partner) into batch_.
  void predict_pairs(int c, double now);

  // The next contact of bodies c and d through the listed pairs pairs_[first, last).
  void predict_pair(int c, int d, std::size_t first, std::size_t last, double now);

  // One step of conservative advancement over the pairs search_range_ of pairs_ (bodies
  // c and d) at time t: touching pair (in touching_) or the safe step.
  PairStep advance_pairs(int c, int d, double t);

  // The collision of the touching pair found by advance_pairs, at time t.
  Event touching_event(double t) const {
    const auto [lo, hi] = touching_;
    return {t, lo, hi, cluster_of(lo).stamp, cluster_of(hi).stamp, EventKind::collision};
  }

  // Resumes the contact search of bodies c and d (d < 0: the wall -1 - d) at time t, and
  // runs it until a contact, the next event in the calendar, or the lists' expiry.
  EventRecord search(int c, int d, double t);

  // ---- walls --------------------------------------------------------------------------------

  // Wall w = 2 a + side: the wall at x_a = 0 (side 0) or x_a = L (side 1).
  double wall_gap(int i, const Vec<D>& x, int w) const {
    const int a = w / 2;
    return (w % 2 == 0 ? x[a] : s_.box.length - x[a]) - s_.spheres.radius[i];
  }

  void predict_walls(int c, double now);

  // Conservative advancement of body c towards wall w from time t, over its spheres within
  // a skin of the wall; the window ends when a farther sphere could have come that close.
  void search_wall(int c, int w, double t);

  EventRecord hit_wall(int i, int w, double t);

  // ---- collisions ---------------------------------------------------------------------------

  // Impact energy: kinetic energy of the two bodies' translation in their centre-of-mass
  // frame, 1/2 mu |V1 - V2|^2 (the energy Richardson's §3 compares with the threshold).
  double impact_energy(int c, int d) const {
    const Cluster<D>& kc = s_.clusters[c];
    const Cluster<D>& kd = s_.clusters[d];
    return 0.5 * kc.mass * kd.mass / (kc.mass + kd.mass) * (kc.velocity - kd.velocity).squaredNorm();
  }

  EventRecord collide(int i, int j, double t);

  void bounce(int i, int j, double t);

  // Bodies of the touching spheres i and j stick at time t. The absorbed (smaller) body's
  // spheres are re-binned and their lists refreshed at once, O(their number): the joined
  // body then carries only the larger one's drift. (Taking the larger drift of the two
  // instead would make a big aggregate that sweeps up monomers rebuild all its lists
  // after nearly every merge.)
  int stick(int i, int j, double t);

  // The foreign pair (lowest sphere ids first) touching body c at time t, if any.
  std::optional<std::pair<int, int>> touching_pair(int c, double t);

  // A body whose bounding sphere is as large as the periodic box may touch its own image,
  // which a rigid body cannot resolve: the run stops there (StopReason::body_spans_box).
  void check_span(int c);

  // Sphere coagulation (models i-ii): the pair and every sphere it then touches become one
  // sphere. Only the spheres whose size, place or id changes are taken out of the grid and
  // the lists and put back, and only their bodies predicted again: the cost of a merge is
  // that of a few list rebuilds, not of the whole system.
  int coalesce(int i, int j, double t, int& merges);

  // One coalescence of spheres i and j at time t; the sphere with the higher id leaves and
  // the last sphere takes its id (State::coalesce_spheres). Returns the merged body.
  int merge_spheres(int i, int j, double t);

  // The lowest-id sphere of another body that sphere i (just grown) touches at time t, or -1.
  int sphere_touching(int i, double t);

  // Takes sphere i out of the lists and the grid; puts it back (after its body, id or size
  // changed) with its foreign neighbours found anew.
  void detach_sphere(int i);
  void attach_sphere(int i, double t);

  // Catastrophic breakup (§2.6) of body c just made at time t: its spheres fly apart with
  // `released` kinetic energy given back. Their mutual contacts become foreign pairs.
  void fragment(int c, double released, double t);

  State<D>& s_;
  RigidBodySettings settings_;
  RigidBodies<D> bodies_;
  NeighborKeeper<RotationDrift<D>> keeper_;  // the skin, drifts and list expiries
  std::unique_ptr<CellGrid<D>> grid_;
  NeighborLists lists_;
  std::vector<Event> batch_;
  std::vector<std::array<int, 3>> pairs_;             // (partner body, sphere of c, sphere of d)
  std::pair<std::size_t, std::size_t> search_range_;  // of pairs_
  std::pair<int, int> touching_{-1, -1};
  std::vector<std::int32_t> near_wall_;
  std::vector<double> pose_time_;
  std::vector<Pose> pose_;
  std::vector<std::int64_t> serial_, partner_;        // body identities, for N_C1
  std::int64_t next_serial_ = 0;
  std::vector<std::int32_t> empty_;                   // ids of clusters without members
  std::vector<char> merged_sphere_;                   // sphere made by coalescence
  std::vector<std::int32_t> renumbered_;              // bodies whose sphere changed id in a coalescence
  double grid_radius_ = 0.0;                          // binned_radius() when the grid was built
  double free_mass_ = 0.0, total_mass_ = 0.0;         // mass in unaggregated spheres
  double aggregated_target_ = kNever;
  bool spans_box_ = false;
  bool resumed_ = false;
  RigidBodyCounters count_;
  EventLoopState loop_;
};

}  // namespace ballagg
