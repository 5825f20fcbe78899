// The rigid-body engine (Richardson 1995). Bodies fly and spin freely between events; an
// event is one of
//   collision       two spheres of different bodies touch: stick (8)-(12), bounce
//                   (13)-(28), or break up (§2.6), as collision.outcome decides;
//   wall            a sphere touches a wall: an elastic, frictionless impulse;
//   contact_search  resume the search for the first contact of two bodies at least one of
//                   which rotates (or of a rotating body and a wall);
//   list_rebuild    a body may have moved half the skin: its neighbour lists expire.
//
// Detection (§2.3). Each sphere lists the spheres of other bodies within sigma + skin
// (spatial/neighbor_lists.hpp, as in the event-driven engine); a sphere's drift bounds its
// body's translation plus the rotation of its lever arm. Two bodies can only touch through
// listed pairs. If neither rotates (single spheres, or no spin) their pairs' contact times
// are exact roots (eq. A.3 of Degond et al.) as in `ed`. Otherwise the bounding spheres of
// radius R_max (7) are tested first, and then the listed pairs sphere by sphere on the
// rotating trajectories, by conservative advancement (contact_search.hpp): a search runs
// until it finds the contact (within kContactGap of a diameter), until the next event
// in the calendar (which might change either body: the search resumes after it), or until
// the lists expire (a rebuild re-predicts).
//
// Positions: a body's centre of mass is the state's cluster anchor, a straight line; its
// orientation comes from the exact free-rotation propagator. The state's sphere offsets
// are written only when an observer reads them (RunObserver::next_position_read) and at
// the end.
#include "ballagg/engines/rigid_body/rigid_body_engine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "ballagg/collision/crossing.hpp"
#include "ballagg/collision/prediction.hpp"
#include "ballagg/collision/rigid_impulse.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/input_error.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"
#include "ballagg/engines/event_driven/event_driven_engine.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/engines/event_driven/neighbor_keeper.hpp"
#include "ballagg/engines/rigid_body/contact_search.hpp"
#include "ballagg/engines/rigid_body/rigid_bodies.hpp"
#include "ballagg/engines/rigid_body/rotation_drift.hpp"
#include "ballagg/spatial/cell_grid.hpp"
#include "ballagg/spatial/neighbor_lists.hpp"

namespace ballagg {
namespace {

// A collision may change the kinetic energy by this fraction of the two bodies' kinetic
// energy (round-off) and still count as not creating energy.
constexpr double kEnergyRoundOff = 1e-10;

template <int D>
class ObservedState;

template <int D>
class RigidBodyCore {
  using Pose = typename RigidBodies<D>::Pose;

 public:
  using Settings = RigidBodySettings;
  RigidBodyCore(State<D>& state, const RigidBodySettings& settings)
      : s_(state), law_(settings),
        keeper_(RotationDrift<D>(state, bodies_), fitted_skin(state, settings.skin, rigid_body_skin(state),
                                                              SkinLimitRounding::multiply_first)) {
    if (law_.coagulation == Coagulation::sphere) {
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
  RigidBodyCore(State<D>& state, const RigidBodySettings& settings, std::string_view saved)
      : s_(state), law_(settings), keeper_(RotationDrift<D>(state, bodies_), 0.0), resumed_(true) {
    const int n = s_.n_spheres();
    const int m = static_cast<int>(s_.clusters.size());
    ByteReader r(saved, "checkpoint of the rigid-body engine");
    count_ = r.get<EngineCounters>("counters");
    loop_ = r.get<EventLoopState>("loop state");
    keeper_.set_skin(r.get<double>("skin"));
    if (!(std::isfinite(keeper_.skin()) && keeper_.skin() > 0.0)) r.fail("neighbour-list skin not a positive number");
    if (r.get<std::int32_t>("sphere count") != n || r.get<std::int32_t>("cluster count") != m)
      r.fail("saved for another number of spheres or clusters");
    s_.spin.resize(m);
    for (ClusterSpin<D>& w : s_.spin) {
      w.angular_velocity = r.get<Spin<D>>("angular velocity");
      w.angular_momentum = r.get<Spin<D>>("angular momentum");
    }
    bodies_.restore(r, m, n);
    grid_ = std::make_unique<CellGrid<D>>(s_.box, binning_cell_size(s_, keeper_.skin()), n);
    if (r.get<double>("cell size") != grid_->cell_size()) r.fail("cell grid for another largest radius or skin");
    grid_->restore(r);
    lists_.reset(n, m);
    lists_.restore(r);
    calendar_.reset(m);
    calendar_.restore(r, [&](const Event& e) {
      const bool ok = e.kind == EventKind::collision        ? e.a >= 0 && e.a < e.b && e.b < n
                      : e.kind == EventKind::wall           ? e.a >= 0 && e.a < n && e.b >= 0 && e.b < 2 * D
                      : e.kind == EventKind::contact_search ? e.a >= 0 && e.a < m && e.b >= -2 * D && e.b < m && e.b != e.a
                      : e.kind == EventKind::list_rebuild && e.a >= 0 && e.a < m;
      if (!ok) r.fail("an event that names no sphere, body or wall");
    });
    pose_time_ = r.get_vector<double>("pose times", m);
    pose_.resize(m);
    for (Pose& p : pose_) {
      p.rotation = r.get<Rotation<D>>("pose");
      p.angular_velocity = r.get<Spin<D>>("pose");
    }
    keeper_.restore(r, m);
    serial_ = r.get_vector<std::int64_t>("body serials", m);
    partner_ = r.get_vector<std::int64_t>("body partners", m);
    next_serial_ = r.get<std::int64_t>("next serial");
    empty_ = r.get_vector<std::int32_t>("empty clusters", m);
    for (std::int32_t c : empty_)
      if (c < 0 || c >= m || s_.clusters[c].alive()) r.fail("an empty cluster that is not empty");
    merged_sphere_ = r.get_vector<char>("merged spheres", n);
    free_mass_ = r.get<double>("free mass");
    total_mass_ = r.get<double>("total mass");
    spans_box_ = r.get<std::uint8_t>("spans box") != 0;
    if (static_cast<int>(pose_time_.size()) != m || static_cast<int>(serial_.size()) != m || static_cast<int>(partner_.size()) != m ||
        static_cast<int>(merged_sphere_.size()) != n)
      r.fail("per-body or per-sphere arrays of another length");
    r.expect_end();
  }

  // Everything the engine carries from one event to the next, the state aside; and the
  // state's spins, which only this engine writes. The state itself is saved as it is: its
  // sphere offsets are those last written (write_state), and the run goes on from the
  // bodies saved here, so the resumed state stays, field by field, the uninterrupted one.
  std::string save() const {
    const int m = static_cast<int>(s_.clusters.size());
    ByteWriter w;
    w.put(count_);
    w.put(loop_);
    w.put(keeper_.skin());
    w.put<std::int32_t>(s_.n_spheres());
    w.put<std::int32_t>(m);
    for (const ClusterSpin<D>& c : s_.spin) w.put(c.angular_velocity), w.put(c.angular_momentum);
    bodies_.save(w);
    w.put(grid_->cell_size());
    grid_->save(w);
    lists_.save(w);
    calendar_.save(w);
    w.put_vector(pose_time_);
    for (const Pose& p : pose_) w.put(p.rotation), w.put(p.angular_velocity);
    keeper_.save(w);
    w.put_vector(serial_);
    w.put_vector(partner_);
    w.put(next_serial_);
    w.put_vector(empty_);
    w.put_vector(merged_sphere_);
    w.put(free_mass_);
    w.put(total_mass_);
    w.put<std::uint8_t>(spans_box_);
    return w.take();
  }

  RunResult run(State<D>& state, const StopCriteria& stop, RunObserver<D>& observer);

  EngineCounters& counters() { return count_; }
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

  std::optional<Event> next_event() {
    return calendar_.pop_valid([&](const Event& e) { return valid(e); });
  }
  void put_back(const Event& e) { calendar_.put_back(e); }

  EventRecord handle(const Event& e) {
    switch (e.kind) {
      case EventKind::collision: return collide(e.a, e.b, e.time);
      case EventKind::wall: return hit_wall(e.a, e.b, e.time);
      case EventKind::contact_search: return search(e.a, e.b, e.time);
      case EventKind::list_rebuild: return rebuild(e.a, e.time);
      case EventKind::time_step: break;  // never queued here
    }
    return {};
  }

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

  // Calls found(j) for every foreign sphere j within sigma + skin of sphere i at time t
  // for which wanted(j) holds (engines/event_driven/neighbor_keeper.hpp).
  template <class Wanted, class Found>
  void for_each_foreign_near(int i, double t, Wanted&& wanted, Found&& found) {
    const Vec<D> xi = unwrapped_position(i, t);
    ballagg::for_each_foreign_near(
        *grid_, s_, keeper_.skin(), body_of(i), s_.box.wrap(xi), s_.spheres.radius[i], wanted,
        [&](int j) { return within_reach(i, xi, j, t); }, found);
  }
  // Whether the pair (i, j) belongs in the lists at time t: closer than sigma + skin. A
  // sphere of a spinning aggregate is not located (that would cost an orientation): it is
  // within its body's drift of where it was binned, and the pair is kept unless even the
  // nearest point of that ball is out of reach. Listing a pair that is a little farther
  // costs a prediction; dropping one only when it is surely out of reach keeps the lists
  // valid.
  bool within_reach(int i, const Vec<D>& xi, int j, double t) {
    const double reach = s_.spheres.radius[i] + s_.spheres.radius[j] + keeper_.skin();
    const int d = body_of(j);
    if (bodies_.translates(s_, d)) return s_.box.separation(xi, unwrapped_position(j, t)).squaredNorm() < reach * reach;
    const double nearest = s_.box.separation(xi, grid_->binned(j)).norm() - keeper_.drift(d, t);
    return nearest < reach;
  }

  // Grid, lists, drifts and every prediction from scratch (start, and after each sphere
  // coalescence, which renumbers a sphere).
  void build_spatial() {
    const int n = s_.n_spheres();
    const int m = static_cast<int>(s_.clusters.size());
    const double t = s_.time;
    grid_ = std::make_unique<CellGrid<D>>(s_.box, binning_cell_size(s_, keeper_.skin()), n);
    pose_time_.assign(m, std::numeric_limits<double>::quiet_NaN());
    pose_.resize(m);
    keeper_.assign(m);
    lists_.reset(n, m);
    calendar_.reset(m);
    for (int i = 0; i < n; ++i) {
      grid_->insert(i, s_.box.wrap(unwrapped_position(i, t)));
      grid_->set_tag(i, body_of(i));
    }
    for (int c : s_.alive_clusters()) keeper_.reset(c, t);
    for (int i = 0; i < n; ++i)
      for_each_foreign_near(i, t, [&](int j) { return j > i; }, [&](int j) { lists_.add_pair(i, j, s_.spheres.cluster.data()); });
    for (int c : s_.alive_clusters()) keeper_.renew_expiry(c);
    for (int c : s_.alive_clusters()) predict(c, /*skip_lower_bodies=*/true);
  }

  // Drops the pairs of sphere i that are out of reach at time t. Removal swaps the last
  // partner into the hole, so walking the list from its end visits every entry once.
  void drop_out_of_reach(int i, double t) {
    const Vec<D> xi = unwrapped_position(i, t);
    for (auto p = static_cast<std::ptrdiff_t>(lists_.partners(i).size()) - 1; p >= 0; --p) {
      const int j = lists_.partners(i)[p];
      if (!within_reach(i, xi, j, t)) lists_.remove_pair(i, j, s_.spheres.cluster.data());
    }
  }

  EventRecord rebuild(int c, double t) {
    const std::int32_t* cluster = s_.spheres.cluster.data();
    for (auto e = static_cast<std::ptrdiff_t>(lists_.exposed(c).size()) - 1; e >= 0; --e)
      drop_out_of_reach(lists_.exposed(c)[e], t);
    for (int i : s_.clusters[c].members) grid_->move(i, s_.box.wrap(unwrapped_position(i, t)));
    keeper_.reset(c, t);
    // Predictions already filed stay valid (exact contact times, or searches that look at
    // the lists when they run). The pairs that came into reach need predictions, and so
    // do the rotating partners, whose last search may have stopped at the old expiry.
    pairs_.clear();
    for (int i : s_.clusters[c].members) {
      for_each_foreign_near(i, t, [&](int j) { return !lists_.listed(i, j); }, [&](int j) {
        lists_.add_pair(i, j, cluster);
        pairs_.push_back({body_of(j), i, j});
      });
    }
    const bool rotating = !bodies_.translates(s_, c);
    for (int i : lists_.exposed(c))
      for (int j : lists_.partners(i))
        if (rotating || !bodies_.translates(s_, body_of(j))) pairs_.push_back({body_of(j), i, j});
    std::sort(pairs_.begin(), pairs_.end());
    pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
    batch_.clear();
    if (keeper_.renew_expiry(c) < kNever) batch_.push_back({keeper_.expiry(c), c, 0, s_.clusters[c].stamp, 0, EventKind::list_rebuild});
    predict_pairs(c, t);
    calendar_.file(c, batch_);
    count_.queue_peak = std::max<std::int64_t>(count_.queue_peak, calendar_.size());
    count_.rebuilt_spheres += s_.clusters[c].size();
    ++count_.list_rebuilds;
    return {.time = t, .kind = EventKind::list_rebuild, .cluster = c};
  }

  // ---- predictions --------------------------------------------------------------------------

  // Files the list rebuild, wall contacts and contacts with every listed partner body of
  // body c, replacing everything filed under c before.
  void predict(int c, bool skip_lower_bodies = false, int skip_body = -1) {
    const double now = s_.time;
    batch_.clear();
    const Cluster<D>& k = s_.clusters[c];
    if (keeper_.renew_expiry(c) < kNever) batch_.push_back({keeper_.expiry(c), c, 0, k.stamp, 0, EventKind::list_rebuild});
    if (!s_.box.periodic()) predict_walls(c, now);
    pairs_.clear();
    for (int i : lists_.exposed(c)) {
      for (int j : lists_.partners(i)) {
        const int d = body_of(j);
        if (d == skip_body || (skip_lower_bodies && d < c)) continue;
        pairs_.push_back({d, i, j});
      }
    }
    std::sort(pairs_.begin(), pairs_.end());
    predict_pairs(c, now);
    calendar_.refile(c, batch_);
    count_.queue_peak = std::max<std::int64_t>(count_.queue_peak, calendar_.size());
  }

  // Predictions of body c with each partner body of pairs_ (sorted by partner) into batch_.
  void predict_pairs(int c, double now) {
    for (std::size_t first = 0; first < pairs_.size();) {
      std::size_t last = first;
      while (last < pairs_.size() && pairs_[last][0] == pairs_[first][0]) ++last;
      predict_pair(c, pairs_[first][0], first, last, now);
      first = last;
    }
  }

  // The next contact of bodies c and d through the listed pairs pairs_[first, last).
  void predict_pair(int c, int d, std::size_t first, std::size_t last, double now) {
    const double limit = std::min(keeper_.expiry(c), keeper_.expiry(d));
    const Cluster<D>& kc = s_.clusters[c];
    const Cluster<D>& kd = s_.clusters[d];
    if (bodies_.translates(s_, c) && bodies_.translates(s_, d)) {
      // Straight lines: exact contact times, as in the event-driven engine.
      for (std::size_t p = first; p < last; ++p) {
        const int i = pairs_[p][1], j = pairs_[p][2];
        const double t = predicted_contact(s_.box, kc, offset(i, now), kd, offset(j, now),
                                           s_.spheres.radius[i] + s_.spheres.radius[j], now, limit);
        ++count_.pair_predictions;
        if (t == kNever) continue;
        const int lo = std::min(i, j), hi = std::max(i, j);
        batch_.push_back({t, lo, hi, cluster_of(lo).stamp, cluster_of(hi).stamp, EventKind::collision});
      }
      return;
    }
    // Bounding spheres first (7): no sphere of c can touch one of d before they meet.
    double start = now;
    const double bound = bodies_[c].radius + bodies_[d].radius;
    const Vec<D> between = s_.box.separation(s_.origin(c, now), s_.origin(d, now));
    if (between.norm() > bound && (!s_.box.periodic() || bound < 0.5 * s_.box.length)) {
      const Vec<D> zero = Vec<D>::Zero();
      start = predicted_contact(s_.box, kc, zero, kd, zero, bound, now, limit);
      if (start >= limit) return;
      if (start > now) {  // the search begins when they do
        batch_.push_back({start, c, d, kc.stamp, kd.stamp, EventKind::contact_search});
        return;
      }
    }
    search_range_ = {first, last};
    const PairStep step = advance_pairs(c, d, start);
    ++count_.pair_predictions;
    if (step.touching) {
      batch_.push_back(touching_event(start));
      return;
    }
    if (start + step.step < limit)
      batch_.push_back({start + step.step, c, d, kc.stamp, kd.stamp, EventKind::contact_search});
  }

  // One step of conservative advancement over the pairs search_range_ of pairs_ (bodies
  // c and d) at time t: touching pair (in touching_) or the safe step.
  PairStep advance_pairs(int c, int d, double t) {
    ++count_.advancement_steps;
    const Cluster<D>& kc = s_.clusters[c];
    const Cluster<D>& kd = s_.clusters[d];
    const Vec<D> xc = s_.origin(c, t), xd = s_.origin(d, t);
    const bool rc = s_.clusters[c].size() > 1, rd = s_.clusters[d].size() > 1;
    const Pose none;
    const Pose& pc = rc ? pose(c, t) : none;
    const Pose& pd = rd ? pose(d, t) : none;
    const double wc = spin_bound(c), wd = spin_bound(d);
    const double ac = rc ? bodies_[c].rotation.max_angular_acceleration() + wc * wc : 0.0;
    const double ad = rd ? bodies_[d].rotation.max_angular_acceleration() + wd * wd : 0.0;
    const double relative_speed = (kc.velocity - kd.velocity).norm();
    PairStep best;
    double best_gap = kNever;
    touching_ = {-1, -1};
    for (std::size_t p = search_range_.first; p < search_range_.second; ++p) {
      const int i = pairs_[p][1], j = pairs_[p][2];
      const Vec<D> oi = rc ? bodies_.offset(i, c, pc) : Vec<D>::Zero();
      const Vec<D> oj = rd ? bodies_.offset(j, d, pd) : Vec<D>::Zero();
      const Vec<D> r = s_.box.separation(Vec<D>(xc + oi), Vec<D>(xd + oj));
      const double sigma = s_.spheres.radius[i] + s_.spheres.radius[j];
      const double distance = r.norm();
      const Vec<D> vi = kc.velocity + cross(pc.angular_velocity, oi);
      const Vec<D> vj = kd.velocity + cross(pd.angular_velocity, oj);
      const double rate = r.dot(vi - vj) / distance;
      const double li = bodies_.reach_of(i, c), lj = bodies_.reach_of(j, d);
      const double speed = relative_speed + wc * li + wd * lj;
      const double curvature = speed * speed / sigma + ac * li + ad * lj;
      const double gap = distance - sigma;
      const PairStep s = advancement_step(gap, rate, kContactGap * sigma, curvature);
      if (s.touching) {
        if (!best.touching || gap < best_gap) {
          best = s;
          best_gap = gap;
          touching_ = {std::min(i, j), std::max(i, j)};
        }
      } else if (!best.touching && s.step < best.step) {
        best.step = s.step;
      }
    }
    return best;
  }

  // The collision of the touching pair found by advance_pairs, at time t.
  Event touching_event(double t) const {
    const auto [lo, hi] = touching_;
    return {t, lo, hi, cluster_of(lo).stamp, cluster_of(hi).stamp, EventKind::collision};
  }

  // Resumes the contact search of bodies c and d (d < 0: the wall -1 - d) at time t, and
  // runs it until a contact, the next event in the calendar, or the lists' expiry.
  EventRecord search(int c, int d, double t) {
    ++count_.contact_searches;
    const EventRecord record{.time = t, .kind = EventKind::contact_search, .cluster = c};
    if (d < 0) {
      search_wall(c, -1 - d, t);
      return record;
    }
    // The listed pairs of c and d, gathered from the body with fewer exposed spheres.
    pairs_.clear();
    const bool from_c = lists_.exposed(c).size() <= lists_.exposed(d).size();
    for (int i : lists_.exposed(from_c ? c : d))
      for (int j : lists_.partners(i))
        if (body_of(j) == (from_c ? d : c)) pairs_.push_back({d, from_c ? i : j, from_c ? j : i});
    if (pairs_.empty()) return record;
    std::sort(pairs_.begin(), pairs_.end());
    search_range_ = {0, pairs_.size()};
    const double limit = std::min(keeper_.expiry(c), keeper_.expiry(d));
    const double horizon = calendar_.earliest_time();
    for (int steps = 0;; ++steps) {
      const PairStep step = advance_pairs(c, d, t);
      if (step.touching) {
        calendar_.file(c, {touching_event(t)});
        return record;
      }
      t += step.step;
      if (t >= limit) return record;
      if (t > horizon || steps + 1 == kMaxStepsPerSearch) {
        calendar_.file(c, {{t, c, d, s_.clusters[c].stamp, s_.clusters[d].stamp, EventKind::contact_search}});
        return record;
      }
    }
  }

  // ---- walls --------------------------------------------------------------------------------

  // Wall w = 2 a + side: the wall at x_a = 0 (side 0) or x_a = L (side 1).
  double wall_gap(int i, const Vec<D>& x, int w) const {
    const int a = w / 2;
    return (w % 2 == 0 ? x[a] : s_.box.length - x[a]) - s_.spheres.radius[i];
  }

  void predict_walls(int c, double now) {
    const Cluster<D>& k = s_.clusters[c];
    const Vec<D> x = s_.origin(c, now);
    for (int w = 0; w < 2 * D; ++w) {
      const int a = w / 2;
      const double towards = w % 2 == 0 ? -k.velocity[a] : k.velocity[a];  // speed towards the wall
      if (k.size() == 1) {
        // A single sphere: its centre moves in a straight line.
        if (towards <= 0.0) continue;
        const int i = k.members.front();
        const double t = now + std::max(wall_gap(i, x, w), 0.0) / towards;
        if (t < kNever) batch_.push_back({t, i, w, k.stamp, 0, EventKind::wall});  // never at a subnormal speed
        continue;
      }
      // The bounding sphere reaches the wall plane first.
      const double gap = (w % 2 == 0 ? x[a] : s_.box.length - x[a]) - bodies_[c].radius;
      double start = now;
      if (gap > 0.0) {
        if (towards <= 0.0) continue;
        start = now + gap / towards;
      }
      if (start < kNever) batch_.push_back({start, c, -1 - w, k.stamp, 0, EventKind::contact_search});
    }
  }

  // Conservative advancement of body c towards wall w from time t, over its spheres within
  // a skin of the wall; the window ends when a farther sphere could have come that close.
  void search_wall(int c, int w, double t) {
    const Cluster<D>& k = s_.clusters[c];
    const int a = w / 2;
    const double omega = spin_bound(c);
    const double alpha = bodies_[c].rotation.max_angular_acceleration() + omega * omega;
    const double towards = std::abs(k.velocity[a]);
    const double window_speed = towards + omega * bodies_[c].reach;
    const double window_end = window_speed > 0.0 ? t + 0.5 * keeper_.skin() / window_speed : kNever;
    near_wall_.clear();
    {
      const Pose& p = pose(c, t);
      const Vec<D> x = s_.origin(c, t);
      for (int i : k.members)
        if (wall_gap(i, Vec<D>(x + bodies_.offset(i, c, p)), w) < keeper_.skin()) near_wall_.push_back(i);
    }
    const double horizon = calendar_.earliest_time();
    for (int steps = 0; !near_wall_.empty(); ++steps) {
      ++count_.advancement_steps;
      const Pose& p = pose(c, t);
      const Vec<D> x = s_.origin(c, t);
      PairStep best;
      int touching = -1;
      double best_gap = kNever;
      for (int i : near_wall_) {
        const Vec<D> o = bodies_.offset(i, c, p);
        const double gap = wall_gap(i, Vec<D>(x + o), w);
        const double v = (k.velocity + cross(p.angular_velocity, o))[a];
        const double rate = w % 2 == 0 ? v : -v;
        const double lever = bodies_.reach_of(i, c);
        const PairStep s = advancement_step(gap, rate, kContactGap * 2.0 * s_.spheres.radius[i], alpha * lever);
        if (s.touching && (touching < 0 || gap < best_gap)) touching = i, best_gap = gap;
        if (!s.touching) best.step = std::min(best.step, s.step);
      }
      if (touching >= 0) {
        calendar_.file(c, {{t, touching, w, k.stamp, 0, EventKind::wall}});
        return;
      }
      t += best.step;
      if (t >= window_end || t > horizon || steps + 1 == kMaxStepsPerSearch) break;
    }
    if (near_wall_.empty()) t = window_end;
    // Resume at t unless the body's bounding sphere has left the wall for good.
    const double gap = (w % 2 == 0 ? s_.origin(c, t)[a] : s_.box.length - s_.origin(c, t)[a]) - bodies_[c].radius;
    const double approach = w % 2 == 0 ? -k.velocity[a] : k.velocity[a];
    if (t < kNever && (gap <= 0.0 || approach > 0.0))
      calendar_.file(c, {{std::max(t, s_.time), c, -1 - w, k.stamp, 0, EventKind::contact_search}});
  }

  EventRecord hit_wall(int i, int w, double t) {
    const int c = body_of(i);
    const int a = w / 2;
    Vec<D> n = Vec<D>::Zero();  // from the body to the wall
    n[a] = w % 2 == 0 ? -1.0 : 1.0;
    const Pose p = pose(c, t);
    const Vec<D> lever = offset(i, t) + s_.spheres.radius[i] * n;
    const ImpactBody<D> body = bodies_.impact_body(s_, c, p, lever);
    const ImpactBody<D> wall;  // infinite mass, at rest
    const Impact<D> impact = collision_impulse(body, wall, n, {});
    if (impact.approaching) {
      keeper_.fold(c, t);
      bodies_.apply_impulse(s_, c, impact.impulse, lever, t);
      s_.add_wall_impulse(impact.impulse);  // the momentum budget (summary.json wall_impulse)
      forget_pose(c);
      ++count_.wall_bounces;
    }
    predict(c);
    return {.time = t, .kind = EventKind::wall, .cluster = c, .axis = a};
  }

  // ---- collisions ---------------------------------------------------------------------------

  // Impact energy: kinetic energy of the two bodies' translation in their centre-of-mass
  // frame, 1/2 mu |V1 - V2|^2 (the energy Richardson's §3 compares with the threshold).
  double impact_energy(int c, int d) const {
    const Cluster<D>& kc = s_.clusters[c];
    const Cluster<D>& kd = s_.clusters[d];
    return 0.5 * kc.mass * kd.mass / (kc.mass + kd.mass) * (kc.velocity - kd.velocity).squaredNorm();
  }

  EventRecord collide(int i, int j, double t) {
    ++count_.collisions;
    EventRecord r{.time = t, .kind = EventKind::collision, .sphere_i = i, .sphere_j = j};
    const int c = body_of(i), d = body_of(j);
    if (!(partner_[c] == serial_[d] && partner_[d] == serial_[c])) ++count_.first_time_collisions;
    partner_[c] = serial_[d];
    partner_[d] = serial_[c];
    const double energy = impact_energy(c, d);
    const bool aggregate = law_.coagulation == Coagulation::aggregate;
    const bool breaks = aggregate && energy >= law_.fragmentation_energy &&
                        (s_.clusters[c].size() > 1 || s_.clusters[d].size() > 1);
    const bool sticks = breaks || law_.outcome == CollisionOutcome::stick ||
                        (law_.outcome == CollisionOutcome::energy_threshold && energy < law_.energy_threshold);
    if (!sticks) {
      bounce(i, j, t);
      r.cluster = c;
      return r;
    }
    if (!aggregate) {
      r.cluster = coalesce(i, j, t, r.merges);
      return r;
    }
    const double before = bodies_.kinetic_energy(s_, c) + bodies_.kinetic_energy(s_, d);
    int keep = stick(i, j, t);
    ++r.merges;
    if (breaks) {
      fragment(keep, before - bodies_.kinetic_energy(s_, keep), t);
      r.cluster = keep;
      return r;
    }
    while (auto pair = touching_pair(keep, t)) {
      keep = stick(pair->first, pair->second, t);
      ++r.merges;
    }
    check_span(keep);
    predict(keep);
    r.cluster = keep;
    return r;
  }

  void bounce(int i, int j, double t) {
    const int c = body_of(i), d = body_of(j);
    const Pose pc = pose(c, t), pd = pose(d, t);
    const Vec<D> oi = offset(i, t), oj = offset(j, t);
    const Vec<D> xi = s_.origin(c, t) + oi;
    const Vec<D> n = s_.box.separation(Vec<D>(s_.origin(d, t) + oj), xi).normalized();  // from i to j
    const Vec<D> lever_c = oi + s_.spheres.radius[i] * n, lever_d = oj - s_.spheres.radius[j] * n;
    const ImpactBody<D> bc = bodies_.impact_body(s_, c, pc, lever_c), bd = bodies_.impact_body(s_, d, pd, lever_d);
    const bool recent = t - s_.clusters[c].last_collision_time < law_.tc_time ||
                        t - s_.clusters[d].last_collision_time < law_.tc_time;
    const double un = (bd.contact_velocity() - bc.contact_velocity()).dot(n);
    ImpactCoefficients k{law_.restitution, law_.mu_t, law_.mu_p};
    if (law_.restitution_law == RestitutionLaw::bridges) k.normal_restitution = bridges_restitution(std::abs(un) * law_.velocity_unit);
    if (recent) k.normal_restitution = 1.0;
    const Impact<D> impact = collision_impulse(bc, bd, n, k);
    ++count_.bounces;
    if (impact.approaching) {
      const double scale = bodies_.kinetic_energy(s_, c) + bodies_.kinetic_energy(s_, d);
      if (!(impact.denominator > 0.0) || impact.energy_change > kEnergyRoundOff * scale) {
        throw InputError(fmt::format(
            "collision.mu_t = {}, collision.mu_p = {}: at t = {} the collision of spheres {} and {} would {} (the "
            "generalised coefficients must not create energy, Brach 1994); use smaller transverse coefficients",
            law_.mu_t, law_.mu_p, t, i, j,
            impact.denominator > 0.0 ? fmt::format("gain {:.3g} of kinetic energy", impact.energy_change)
                                     : std::string("pull the bodies together")));
      }
      keeper_.fold(c, t);
      keeper_.fold(d, t);
      bodies_.apply_impulse(s_, c, impact.impulse, lever_c, t);
      bodies_.apply_impulse(s_, d, Vec<D>(-impact.impulse), lever_d, t);
      forget_pose(c);
      forget_pose(d);
    }
    s_.clusters[c].last_collision_time = s_.clusters[d].last_collision_time = t;
    // Both motions changed: c's predictions must see d's new list expiry.
    keeper_.renew_expiry(d);
    predict(c);
    predict(d, false, c);
  }

  // Bodies of the touching spheres i and j stick at time t. The absorbed (smaller) body's
  // spheres are re-binned and their lists refreshed at once, O(their number): the joined
  // body then carries only the larger one's drift. (Taking the larger drift of the two
  // instead would make a big aggregate that sweeps up monomers rebuild all its lists
  // after nearly every merge.)
  int stick(int i, int j, double t) {
    const int a = body_of(i), b = body_of(j);
    for (int c : {a, b})
      if (s_.clusters[c].size() == 1 && !merged_sphere_[s_.clusters[c].members.front()]) free_mass_ -= s_.clusters[c].mass;
    const int absorbed = std::min(s_.clusters[a].size(), s_.clusters[b].size());
    // The survivor is the larger body (RigidBodies::stick); its drift so far carries over.
    const int larger = s_.clusters[b].size() > s_.clusters[a].size() || (s_.clusters[b].size() == s_.clusters[a].size() && b < a) ? b : a;
    const double slack = keeper_.drift(larger, t);
    const int keep = bodies_.stick(s_, i, j, t);
    const int gone = keep == a ? b : a;
    const std::int32_t* cluster = s_.spheres.cluster.data();
    const std::vector<std::int32_t>& members = s_.clusters[keep].members;  // absorbed ones last
    for (auto m = members.end() - absorbed; m != members.end(); ++m) grid_->set_tag(*m, keep);
    lists_.absorb(keep, gone, cluster);
    calendar_.forget(gone);
    keeper_.restart(keep, slack);
    forget_pose(keep);
    forget_pose(gone);
    for (auto m = members.end() - absorbed; m != members.end(); ++m) {
      const int k = *m;
      grid_->move(k, s_.box.wrap(unwrapped_position(k, t)));
      drop_out_of_reach(k, t);
      for_each_foreign_near(k, t, [&](int j2) { return !lists_.listed(k, j2); }, [&](int j2) { lists_.add_pair(k, j2, cluster); });
    }
    forget_pose(keep);
    forget_pose(gone);
    serial_[keep] = next_serial_++;
    partner_[keep] = -1;
    empty_.push_back(gone);
    ++count_.merges;
    return keep;
  }

  // The foreign pair (lowest sphere ids first) touching body c at time t, if any.
  std::optional<std::pair<int, int>> touching_pair(int c, double t) {
    std::optional<std::pair<int, int>> best;
    for (int i : lists_.exposed(c)) {
      const Vec<D> xi = unwrapped_position(i, t);
      for (int j : lists_.partners(i)) {
        const double sigma = (s_.spheres.radius[i] + s_.spheres.radius[j]) * (1.0 + tolerance::kContact);
        if (s_.box.separation(xi, unwrapped_position(j, t)).squaredNorm() > sigma * sigma) continue;
        const std::pair<int, int> p{std::min(i, j), std::max(i, j)};
        if (!best || p < *best) best = p;
      }
    }
    return best;
  }

  // A body whose bounding sphere is as large as the periodic box may touch its own image,
  // which a rigid body cannot resolve: the run stops there (StopReason::body_spans_box).
  void check_span(int c) {
    if (!s_.box.periodic()) return;
    const double limit = 0.5 * (s_.box.length - keeper_.skin());
    auto too_big = [&](int b) { return bodies_[b].radius >= limit; };
    if (c >= 0) spans_box_ = spans_box_ || too_big(c);
    else for (int b : s_.alive_clusters()) spans_box_ = spans_box_ || too_big(b);
  }

  // Sphere coagulation (models i-ii): the pair and every sphere it then touches become one
  // sphere. Sphere ids change, so the lists and predictions are rebuilt: O(N) per merge,
  // meant for the test models.
  int coalesce(int i, int j, double t, int& merges) {
    const double r0 = s_.spheres.radius[i], r1 = s_.spheres.radius[j];
    const double radius = law_.merged_radius == MergedRadius::fixed ? r0 : std::cbrt(r0 * r0 * r0 + r1 * r1 * r1);
    for (int sphere : {i, j})
      if (!merged_sphere_[sphere]) free_mass_ -= s_.spheres.mass[sphere];
    const int lo = std::min(i, j), hi = std::max(i, j);
    const int keep = body_of(lo), gone = body_of(hi);
    const int moved = bodies_.coalesce(s_, lo, hi, radius, law_.merged_speed, t);
    merged_sphere_[lo] = 1;
    if (moved >= 0) merged_sphere_[hi] = merged_sphere_[moved];
    merged_sphere_.pop_back();
    empty_.push_back(gone);
    ++merges;
    ++count_.merges;
    serial_[keep] = next_serial_++;
    partner_[keep] = -1;
    build_spatial();
    // A grown sphere may overlap its neighbours: they join it at once.
    for (int p = 0; p < s_.n_spheres(); ++p) {
      if (p == lo) continue;
      const double sigma = (s_.spheres.radius[lo] + s_.spheres.radius[p]) * (1.0 + tolerance::kContact);
      if (s_.box.separation(s_.origin(keep, t), s_.origin(body_of(p), t)).squaredNorm() <= sigma * sigma)
        return coalesce(lo, p, t, merges);
    }
    return keep;
  }

  // Catastrophic breakup (§2.6) of body c just made at time t: its spheres fly apart with
  // `released` kinetic energy given back. Their mutual contacts become foreign pairs.
  void fragment(int c, double released, double t) {
    const std::int32_t* cluster = s_.spheres.cluster.data();
    const std::vector<std::int32_t> members = s_.clusters[c].members;
    const double slack = keeper_.drift(c, t);
    for (int i : members) lists_.remove_all_pairs(i, cluster);
    const std::vector<std::int32_t> pieces = bodies_.fragment(s_, c, released, empty_, t);
    ++count_.fragmentations;
    for (std::size_t k = 0; k < members.size(); ++k) {
      const int i = members[k], b = pieces[k];
      grid_->set_tag(i, b);
      forget_pose(b);
      keeper_.restart(b, slack);
      serial_[b] = next_serial_++;
      partner_[b] = -1;
      free_mass_ += s_.spheres.mass[i];
    }
    for (int i : members)
      for_each_foreign_near(i, t, [&](int j) { return !lists_.listed(i, j); }, [&](int j) { lists_.add_pair(i, j, cluster); });
    for (int b : pieces) keeper_.renew_expiry(b);  // each piece's predictions see the others'
    for (int b : pieces) predict(b);
  }

  State<D>& s_;
  RigidBodySettings law_;
  RigidBodies<D> bodies_;
  NeighborKeeper<RotationDrift<D>> keeper_;  // the skin, drifts and list expiries
  std::unique_ptr<CellGrid<D>> grid_;
  NeighborLists lists_;
  EventCalendar calendar_;
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
  double free_mass_ = 0.0, total_mass_ = 0.0;         // mass in unaggregated spheres
  double aggregated_target_ = kNever;
  bool spans_box_ = false;
  bool resumed_ = false;
  EngineCounters count_;
  EventLoopState loop_;
};

// Keeps the state exact whenever an observer reads it (RunObserver::next_position_read).
template <int D>
class ObservedState final : public RunObserver<D> {
 public:
  ObservedState(RigidBodyCore<D>& core, State<D>& state, RunObserver<D>& inner)
      : core_(core), s_(state), inner_(inner) {}

  void on_start(const State<D>& s) override {
    if (!core_.take_resumed()) core_.write_state(s.time);
    inner_.on_start(s);
  }
  void before_event(const State<D>& s, double t) override {
    for (double read = inner_.next_position_read(); read < t && read >= s_.time;) {
      s_.time = read;
      core_.write_state(read);
      inner_.before_event(s, std::nextafter(read, kNever));
      const double next = inner_.next_position_read();
      if (!(next > read)) break;  // the observer did not move on: do not loop
      read = next;
    }
    inner_.before_event(s, t);
  }
  void after_event(const State<D>& s, const EventRecord& e, const EngineCounters& c) override {
    if (inner_.next_position_read() <= s.time) core_.write_state(s.time);
    inner_.after_event(s, e, c);
  }
  void on_finish(const State<D>& s, const RunResult& r) override {
    core_.write_state(s.time);
    inner_.on_finish(s, r);
  }
  bool checkpoint_due() override { return inner_.checkpoint_due(); }
  void on_checkpoint(const State<D>& s, const EngineCounters& c, const std::string& engine_state) override {
    inner_.on_checkpoint(s, c, engine_state);
  }

 private:
  RigidBodyCore<D>& core_;
  State<D>& s_;
  RunObserver<D>& inner_;
};

template <int D>
RunResult RigidBodyCore<D>::run(State<D>& state, const StopCriteria& stop, RunObserver<D>& observer) {
  set_aggregated_target(stop.aggregated_fraction);
  ObservedState<D> observed(*this, state, observer);
  const RunResult r = run_event_loop(*this, state, stop, observed);
  write_state(state.time);
  return r;
}

}  // namespace

template <int D>
double rigid_body_skin(const State<D>& s) {
  return std::min(default_skin(s), kSkinDiameters * 2.0 * s.mean_radius());
}

template <int D>
std::unique_ptr<Engine<D>> make_rigid_body_engine(const RigidBodySettings& settings) {
  return std::make_unique<EventLoopEngine<D, RigidBodyCore<D>>>("rigid-body", settings);
}

template double rigid_body_skin<2>(const State<2>&);
template double rigid_body_skin<3>(const State<3>&);
template std::unique_ptr<Engine<2>> make_rigid_body_engine<2>(const RigidBodySettings&);
template std::unique_ptr<Engine<3>> make_rigid_body_engine<3>(const RigidBodySettings&);

}  // namespace ballagg
