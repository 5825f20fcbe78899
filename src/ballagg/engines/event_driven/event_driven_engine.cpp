// The exact event-driven engine. One event is one of:
//   collision     two spheres of different clusters touch: stick (rule 2.9) or bounce (2.6);
//   wall          a cluster's bounding box touches a wall it moves towards (rule 2.2);
//   list_rebuild  a cluster may have moved half the skin: its neighbour lists expire.
//
// What must be re-predicted when a cluster's velocity changes? Only the pairs formed by
// its *exposed* spheres (those with foreign neighbours within sigma + skin) and its own
// wall and rebuild times. Its partners' other predictions stay valid: a stale event is
// recognised by its stamps when it reaches the top of the queue. Positions are evaluated
// lazily from each cluster's anchor, so moving a cluster costs nothing.
//
// A list rebuild changes no motion: it drops the pairs now out of reach, adds and
// predicts the new ones, and keeps every prediction already made (they are exact
// predictions whatever the lists say). Pair predictions are therefore never cut off at a
// rebuild horizon.
//
// Why the lists stay valid: a pair absent from the lists was farther apart than
// sigma + skin at the later of its two clusters' last rebuilds, and since then each sphere
// has moved at most skin / 2 from where it was binned, so the pair is still apart.
//
// How far a cluster's spheres may have moved (its drift) is bounded by slack + |d|, where
// d is the cluster's displacement since a reference instant (walls and periodic wraps
// included) and slack covers what happened before it. A rebuild sets both to zero. A
// merge starts a new reference with the larger drift of the two as slack. Displacement
// rather than path length means a big cluster rattling between walls, or bouncing to and
// fro, does not rebuild its lists for nothing.
#include "ballagg/engines/event_driven/event_driven_engine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>

#include "ballagg/collision/prediction.hpp"
#include "ballagg/collision/resolve.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/prefetch.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/spatial/cell_grid.hpp"
#include "ballagg/spatial/neighbor_lists.hpp"

namespace ballagg {
namespace {

template <int D>
class EventDrivenCore {
 public:
  using Settings = EventDrivenSettings;
  EventDrivenCore(State<D>& state, const EventDrivenSettings& settings) : EventDrivenCore(state, settings, Sized{}) {
    const int n = s_.n_spheres();
    const int m = static_cast<int>(s_.clusters.size());
    drift_.assign(m, Drift{});
    rebuild_at_.assign(m, kNever);
    lists_.reset(n, m);
    calendar_.reset(m);
    for (int i = 0; i < n; ++i) {
      grid_.insert(i, s_.position(i, s_.time));
      grid_.set_tag(i, sphere_[i].cluster);
    }
    for (int c = 0; c < m; ++c)
      if (s_.clusters[c].alive()) reset_drift(c, s_.time);
    for (int i = 0; i < n; ++i)
      for_each_foreign_near(i, s_.time, [&](int j) { return j > i; },
                            [&](int j) { lists_.add_pair(i, j, s_.spheres.cluster.data()); });
    for (int c : s_.alive_clusters()) rebuild_at_[c] = rebuild_time(c);
    for (int c = 0; c < m; ++c)
      if (s_.clusters[c].alive()) predict(c, /*skip_lower_clusters=*/true);
  }

  // Restores what save() wrote for this state (a checkpoint): nothing is predicted again,
  // so the run continues with the very events the saved one would have handled.
  EventDrivenCore(State<D>& state, const EventDrivenSettings& settings, std::string_view saved)
      : EventDrivenCore(state, settings, Sized{}) {
    const int n = s_.n_spheres();
    const int m = static_cast<int>(s_.clusters.size());
    ByteReader r(saved, "checkpoint of the ed engine");
    count_ = r.get<EngineCounters>("counters");
    loop_ = r.get<EventLoopState>("loop state");
    if (r.get<double>("skin") != skin_) r.fail("neighbour-list skin differs from the configuration's");
    if (r.get<std::int32_t>("sphere count") != n || r.get<std::int32_t>("cluster count") != m)
      r.fail("saved for another number of spheres or clusters");
    grid_.restore(r);
    lists_.reset(n, m);
    lists_.restore(r);
    calendar_.reset(m);
    calendar_.restore(r, [&](const Event& e) {
      const bool ok = e.kind == EventKind::collision ? e.a >= 0 && e.a < e.b && e.b < n
                      : e.kind == EventKind::wall    ? e.a >= 0 && e.a < m && e.b >= 0 && e.b < D
                      : e.kind == EventKind::list_rebuild && e.a >= 0 && e.a < m;
      if (!ok) r.fail("an event that names no sphere or cluster");
    });
    drift_.resize(m);
    for (Drift& d : drift_) {
      d.displacement_at_anchor = r.get<Vec<D>>("drift");
      d.slack = r.get<double>("drift slack");
    }
    rebuild_at_ = r.get_vector<double>("rebuild times", m);
    if (static_cast<int>(rebuild_at_.size()) != m) r.fail("rebuild times for another number of clusters");
    r.expect_end();
  }

  // Everything the engine carries from one event to the next (the state aside).
  std::string save() const {
    ByteWriter w;
    w.put(count_);
    w.put(loop_);
    w.put(skin_);
    w.put<std::int32_t>(s_.n_spheres());
    w.put<std::int32_t>(static_cast<std::int32_t>(s_.clusters.size()));
    grid_.save(w);
    lists_.save(w);
    calendar_.save(w);
    for (const Drift& d : drift_) {
      w.put(d.displacement_at_anchor);
      w.put(d.slack);
    }
    w.put_vector(rebuild_at_);
    return w.take();
  }

  EngineCounters& counters() { return count_; }
  EventLoopState& loop() { return loop_; }

  std::optional<Event> next_event() {
    return calendar_.pop_valid([&](const Event& e) { return valid(e); });
  }
  void put_back(const Event& e) { calendar_.put_back(e); }

  EventRecord handle(const Event& e) {
    switch (e.kind) {
      case EventKind::collision: return collide(e.a, e.b, e.time);
      case EventKind::wall: return reflect(e.a, e.b, e.time);
      case EventKind::list_rebuild: return rebuild(e.a, e.time);
      case EventKind::time_step: break;       // never queued here: time stepping only
      case EventKind::contact_search: break;  // never queued here: rigid bodies only
    }
    return {};
  }

 private:
  // The members fixed by the settings and the state, and the sphere fields.
  struct Sized {};
  EventDrivenCore(State<D>& state, const EventDrivenSettings& settings, Sized)
      : s_(state), law_(settings.collision), skin_(choose_skin(state, settings.skin)),
        grid_(state.box, 2.0 * state.max_radius() + 1.5 * skin_, state.n_spheres()) {
    sphere_.resize(s_.n_spheres());
    for (int i = 0; i < s_.n_spheres(); ++i) refresh_sphere(i);
  }

  // The requested skin, or default_skin(). Periodic boxes need every listed pair to be
  // closer than half the box, so the skin shrinks in a small periodic box.
  static double choose_skin(const State<D>& s, double requested) {
    double skin = requested > 0.0 ? requested : default_skin(s);
    if (s.box.periodic()) {
      const double room = (0.5 * s.box.length - 2.0 * s.max_radius()) / 1.5;
      skin = std::min(skin, 0.99 * room);
    }
    return skin;
  }

  bool valid(const Event& e) const {
    if (e.kind == EventKind::collision) {
      return cluster_of(e.a).stamp == e.stamp_a && cluster_of(e.b).stamp == e.stamp_b;
    }
    return s_.clusters[e.a].stamp == e.stamp_a;
  }

  // ---- neighbour lists -------------------------------------------------------------------

  Vec<D> displacement(int c, double t) const {
    const Cluster<D>& k = s_.clusters[c];
    return drift_[c].displacement_at_anchor + (t - k.anchor_time) * k.velocity;
  }
  // Upper bound on how far any sphere of cluster c is from where it was binned.
  double drift(int c, double t) const { return drift_[c].slack + displacement(c, t).norm(); }
  // Must be called just before cluster c is re-anchored at t (velocity change).
  void fold_drift(int c, double t) { drift_[c].displacement_at_anchor = displacement(c, t); }
  void reset_drift(int c, double t) {
    const Cluster<D>& k = s_.clusters[c];
    drift_[c] = {-(t - k.anchor_time) * k.velocity, 0.0};
  }

  // When the drift of cluster c reaches skin / 2: the later root tau of
  // |d0 + V tau| = skin / 2 - slack (tau from the anchor time). The cluster is within
  // reach now, so the two roots bracket the present and the later one is the exit.
  double rebuild_time(int c) const {
    const Cluster<D>& k = s_.clusters[c];
    const double a = k.velocity.squaredNorm();
    if (a == 0.0) return kNever;
    const Vec<D>& d0 = drift_[c].displacement_at_anchor;
    const double reach = 0.5 * skin_ - drift_[c].slack;
    const double b = d0.dot(k.velocity), cc = d0.squaredNorm() - reach * reach;
    const double disc = b * b - a * cc;
    if (reach <= 0.0 || disc < 0.0) return k.anchor_time;
    const double root = std::sqrt(disc);
    return k.anchor_time + (b <= 0.0 ? (root - b) / a : -cc / (b + root));
  }

  // Calls found(j) for every foreign sphere j within sigma + skin of sphere i at time t
  // for which wanted(j) holds (asked before the exact distance, which is dearer). The grid
  // tags each sphere with its cluster, so i's own cluster is skipped there; it holds each
  // sphere where it was binned, at most skin / 2 from where it is now, so spheres binned
  // farther than R_i + R_max + 1.5 skin away are rejected at once.
  template <class Wanted, class Found>
  void for_each_foreign_near(int i, double t, Wanted&& wanted, Found&& found) const {
    const int ci = sphere_[i].cluster;
    const Vec<D> xi = unwrapped_position(i, t);
    const Vec<D> xi_folded = s_.box.wrap(xi);
    const double ri = sphere_[i].radius;
    const double binned_reach = ri + s_.max_radius() + 1.5 * skin_;
    grid_.for_each_near_image(xi_folded, ci, [&](int j, const Vec<D>& binned) {
      if ((xi_folded - binned).squaredNorm() >= binned_reach * binned_reach) return;
      if (!wanted(j)) return;
      if (within_reach(i, xi, j, t)) found(j);
    });
  }

  bool within_reach(int i, const Vec<D>& xi, int j, double t) const {
    const double reach = sphere_[i].radius + sphere_[j].radius + skin_;
    return s_.box.separation(xi, unwrapped_position(j, t)).squaredNorm() < reach * reach;
  }

  EventRecord rebuild(int c, double t) {
    const std::int32_t* cluster = s_.spheres.cluster.data();
    const Cluster<D>& k = s_.clusters[c];
    // Drop the pairs that are now out of reach. Removal swaps the last entry of a list
    // into the hole, so walking each list from its end visits every entry once.
    for (auto e = static_cast<std::ptrdiff_t>(lists_.exposed(c).size()) - 1; e >= 0; --e) {
      const int i = lists_.exposed(c)[e];
      prefetch_partners(i);
      const Vec<D> xi = unwrapped_position(i, t);
      for (auto p = static_cast<std::ptrdiff_t>(lists_.partners(i).size()) - 1; p >= 0; --p) {
        const int j = lists_.partners(i)[p];
        if (!within_reach(i, xi, j, t)) lists_.remove_pair(i, j, cluster);
      }
    }
    // Re-bin, then list and predict the pairs that came into reach.
    for (int i : k.members) grid_.move(i, s_.box.wrap(unwrapped_position(i, t)));
    reset_drift(c, t);
    rebuild_at_[c] = rebuild_time(c);
    batch_.clear();
    for (int i : k.members) {
      for_each_foreign_near(i, t, [&](int j) { return !lists_.listed(i, j); }, [&](int j) {
        lists_.add_pair(i, j, cluster);
        if (auto e = pair_event(i, j)) batch_.push_back(*e);
      });
    }
    if (rebuild_at_[c] < kNever) batch_.push_back({rebuild_at_[c], c, 0, k.stamp, 0, EventKind::list_rebuild});
    calendar_.file(c, batch_);
    count_.rebuilt_spheres += k.size();
    ++count_.list_rebuilds;
    return {.time = t, .kind = EventKind::list_rebuild, .cluster = c};
  }

  // ---- predictions -----------------------------------------------------------------------

  // Starts loading what the pairs of sphere i are about to read: its partners' fields,
  // then their clusters. At large N each is a cache miss; requested together they overlap
  // instead of each waiting for the prediction before it.
  void prefetch_partners(int i) const {
    const std::span<const std::int32_t> partners = lists_.partners(i);
    for (int j : partners) prefetch(&sphere_[j]);
    for (int j : partners) {
      const int d = sphere_[j].cluster;
      prefetch(&s_.clusters[d]);
      prefetch(&rebuild_at_[d]);
    }
  }

  // The contact event of spheres i and j (different clusters), if they approach. The
  // periodic image walk stops at the earlier list rebuild of the two clusters: a contact
  // through a farther image needs the pair to leave and re-enter the lists first.
  std::optional<Event> pair_event(int i, int j) {
    const SphereFields& si = sphere_[i];
    const SphereFields& sj = sphere_[j];
    const double limit = std::min(rebuild_at_[si.cluster], rebuild_at_[sj.cluster]);
    const double t = predicted_contact(s_.box, s_.clusters[si.cluster], si.offset, s_.clusters[sj.cluster], sj.offset,
                                       si.radius + sj.radius, s_.time, limit);
    ++count_.pair_predictions;
    if (t == kNever) return std::nullopt;
    const int lo = std::min(i, j), hi = std::max(i, j);
    return Event{t, lo, hi, cluster_of(lo).stamp, cluster_of(hi).stamp, EventKind::collision};
  }

  // Files the next wall contact, list rebuild and pair contacts of cluster c, replacing
  // everything filed under c before (all of it involved c's previous motion).
  void predict(int c, bool skip_lower_clusters = false, int skip_cluster = -1) {
    const Cluster<D>& k = s_.clusters[c];
    batch_.clear();
    const WallContact w = next_wall_contact(s_, c);
    if (w.time < kNever) batch_.push_back({w.time, c, w.axis, k.stamp, 0, EventKind::wall});
    rebuild_at_[c] = rebuild_time(c);
    if (rebuild_at_[c] < kNever) batch_.push_back({rebuild_at_[c], c, 0, k.stamp, 0, EventKind::list_rebuild});
    for (int i : lists_.exposed(c)) {
      prefetch_partners(i);
      for (int j : lists_.partners(i)) {
        const int d = sphere_[j].cluster;
        if (d == skip_cluster || (skip_lower_clusters && d < c)) continue;
        if (auto e = pair_event(i, j)) batch_.push_back(*e);
      }
    }
    calendar_.refile(c, batch_);
    count_.queue_peak = std::max<std::int64_t>(count_.queue_peak, calendar_.size());
  }

  // ---- event handlers --------------------------------------------------------------------

  EventRecord reflect(int c, int axis, double t) {
    fold_drift(c, t);
    reflect_cluster(s_, c, axis, t);
    predict(c);
    ++count_.wall_bounces;
    return {.time = t, .kind = EventKind::wall, .cluster = c, .axis = axis};
  }

  EventRecord collide(int i, int j, double t) {
    ++count_.collisions;
    EventRecord r{.time = t, .kind = EventKind::collision, .sphere_i = i, .sphere_j = j};
    const int a = s_.spheres.cluster[i], b = s_.spheres.cluster[j];
    if (law_.outcome == CollisionOutcome::bounce) {
      fold_drift(a, t);
      fold_drift(b, t);
      bounce_clusters(s_, i, j, t, law_);
      predict(a);
      predict(b, false, a);
      ++count_.bounces;
      r.cluster = a;
      return r;
    }
    int keep = stick(i, j, t);
    ++r.merges;
    // Contact cascade: a sphere touching the new cluster at this instant sticks too.
    while (auto pair = touching_pair(keep, t)) {
      keep = stick(pair->first, pair->second, t);
      ++r.merges;
    }
    predict(keep);
    r.cluster = keep;
    return r;
  }

  int stick(int i, int j, double t) {
    const int a = s_.spheres.cluster[i], b = s_.spheres.cluster[j];
    const double slack = std::max(drift(a, t), drift(b, t));
    const int absorbed = std::min(s_.clusters[a].size(), s_.clusters[b].size());
    const int keep = s_.merge(i, j, t);
    const int gone = keep == a ? b : a;
    const std::vector<std::int32_t>& members = s_.clusters[keep].members;  // absorbed ones last
    for (auto m = members.end() - absorbed; m != members.end(); ++m) {
      refresh_sphere(*m);
      grid_.set_tag(*m, keep);
    }
    lists_.absorb(keep, gone, s_.spheres.cluster.data());
    calendar_.forget(gone);
    drift_[keep] = {Vec<D>::Zero(), slack};
    ++count_.merges;
    return keep;
  }

  // The foreign pair (lowest sphere ids first) touching cluster c at time t, if any.
  std::optional<std::pair<int, int>> touching_pair(int c, double t) const {
    std::optional<std::pair<int, int>> best;
    for (int i : lists_.exposed(c)) {
      for (int j : lists_.partners(i)) {
        if (!touching(s_, i, j, t)) continue;
        const std::pair<int, int> p{std::min(i, j), std::max(i, j)};
        if (!best || p < *best) best = p;
      }
    }
    return best;
  }

  // ---- sphere fields ---------------------------------------------------------------------

  // The fields of a sphere that every prediction and list scan reads, side by side: the
  // state keeps them in three arrays, three cache misses per sphere at large N. They change
  // only when the sphere's cluster is absorbed by another (stick()).
  struct SphereFields {
    Vec<D> offset;
    double radius;
    std::int32_t cluster;
  };
  void refresh_sphere(int i) { sphere_[i] = {s_.spheres.offset[i], s_.spheres.radius[i], s_.spheres.cluster[i]}; }
  const Cluster<D>& cluster_of(int i) const { return s_.clusters[sphere_[i].cluster]; }
  Vec<D> unwrapped_position(int i, double t) const {
    return position_in(cluster_of(i), sphere_[i].offset, t);
  }

  State<D>& s_;
  CollisionSettings law_;
  std::vector<SphereFields> sphere_;
  double skin_;
  CellGrid<D> grid_;
  NeighborLists lists_;
  EventCalendar calendar_;
  std::vector<Event> batch_;         // scratch for predict() and rebuild()
  struct Drift {
    Vec<D> displacement_at_anchor = Vec<D>::Zero();  // since the reference instant
    double slack = 0.0;                               // drift before the reference instant
  };
  std::vector<Drift> drift_;
  // rebuild_time(c) as of c's last prediction: every change of c is followed by predict(c).
  std::vector<double> rebuild_at_;
  EngineCounters count_;
  EventLoopState loop_;
};

}  // namespace

template <int D>
double default_skin(const State<D>& s) {
  // Radius r of the ball holding kSkinNeighbours centres at number density n.
  const double density = s.n_spheres() / s.box.volume();
  const double unit_ball = D == 2 ? std::numbers::pi : 4.0 / 3.0 * std::numbers::pi;
  const double reach = std::pow(kSkinNeighbours / (density * unit_ball), 1.0 / D);
  return std::max(reach - 2.0 * s.mean_radius(), kMinSkin * s.mean_radius());
}

template <int D>
std::unique_ptr<Engine<D>> make_event_driven_engine(const EventDrivenSettings& settings) {
  return std::make_unique<EventLoopEngine<D, EventDrivenCore<D>>>("ed", settings);
}

template double default_skin<2>(const State<2>&);
template double default_skin<3>(const State<3>&);
template std::unique_ptr<Engine<2>> make_event_driven_engine<2>(const EventDrivenSettings&);
template std::unique_ptr<Engine<3>> make_event_driven_engine<3>(const EventDrivenSettings&);

}  // namespace ballagg
