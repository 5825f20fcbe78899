// The exact event-driven engine. One event is one of:
//   collision     two spheres of different clusters touch: stick (rule 2.9) or bounce (2.6);
//   wall          a cluster's bounding box touches a wall it moves towards (rule 2.2);
//   list_rebuild  a cluster may have moved half the skin: its neighbour lists expire.
//
// What must be re-predicted when a cluster's velocity changes? Only the pairs formed by
// its *exposed* spheres (those with foreign neighbours in their lists) and its own
// wall and rebuild times. Its partners' other predictions stay valid: a stale event is
// recognised by its stamps when it reaches the top of the queue. Positions are evaluated
// lazily from each cluster's anchor, so moving a cluster costs nothing.
//
// A list rebuild changes no motion: it drops the pairs now out of reach, adds and
// predicts the new ones, and keeps every prediction already made (they are exact
// predictions whatever the lists say). Pair predictions are therefore never cut off at a
// rebuild horizon.
//
// Why the lists stay valid, and when they expire: engines/event_driven/neighbor_keeper.hpp;
// how far a cluster's spheres may have moved (its drift): translation_drift.hpp. A merge
// starts a new reference instant with the larger drift of the two as slack.
#include "ballagg/engines/event_driven/event_driven_engine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>

#include "ballagg/collision/crossing.hpp"
#include "ballagg/collision/prediction.hpp"
#include "ballagg/collision/resolve.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/prefetch.hpp"
#include "ballagg/engines/event_driven/calendar_dispatch.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"
#include "ballagg/engines/event_driven/event_driven_counters.hpp"
#include "ballagg/engines/event_driven/event_loop.hpp"
#include "ballagg/engines/event_driven/neighbor_keeper.hpp"
#include "ballagg/engines/event_driven/translation_drift.hpp"
#include "ballagg/spatial/cell_grid.hpp"
#include "ballagg/spatial/neighbor_lists.hpp"

namespace ballagg {
namespace {

template <int D>
class EventDrivenCore : public CalendarDispatch<EventDrivenCore<D>> {
  friend class CalendarDispatch<EventDrivenCore<D>>;
  using CalendarDispatch<EventDrivenCore<D>>::calendar_;

 public:
  using Settings = EventDrivenSettings;
  EventDrivenCore(State<D>& state, const EventDrivenSettings& settings) : EventDrivenCore(state, settings, Sized{}) {
    const int n = s_.n_spheres();
    const int m = static_cast<int>(s_.clusters.size());
    keeper_.assign(m, keeps_expiries());
    lists_.reset(n, m);
    calendar_.reset(m, settings.calendar);
    for (int i = 0; i < n; ++i) {
      grid_.insert(i, s_.position(i, s_.time));
      grid_.set_tag(i, s_.spheres.cluster[i]);
    }
    for (int c = 0; c < m; ++c)
      if (s_.clusters[c].alive()) keeper_.reset(c, s_.time);
    for (int i = 0; i < n; ++i)
      for_each_foreign_near(i, [&](int j) { return j > i; },
                            [&](int j) { lists_.add_pair(i, j, s_.spheres.cluster.data()); });
    for (int c : s_.alive_clusters()) keeper_.renew_expiry(c);
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
    count_.restore(r);
    loop_ = r.get<EventLoopState>("loop state");
    if (r.get<double>("skin") != keeper_.skin()) r.fail("neighbour-list skin differs from the configuration's");
    if (r.get<std::int32_t>("sphere count") != n || r.get<std::int32_t>("cluster count") != m)
      r.fail("saved for another number of spheres or clusters");
    grid_.restore(r);
    lists_.reset(n, m);
    lists_.restore(r);
    calendar_.reset(m, settings.calendar);
    calendar_.restore(r, [&](const Event& e) {
      const bool ok = e.kind == EventKind::collision ? e.a >= 0 && e.a < e.b && e.b < n
                      : e.kind == EventKind::wall    ? e.a >= 0 && e.a < m && e.b >= 0 && e.b < D
                      : e.kind == EventKind::list_rebuild && e.a >= 0 && e.a < m;
      if (!ok) r.fail("an event that names no sphere or cluster");
    });
    keeper_.restore(r, m, keeps_expiries());
    r.expect_end();
  }

  // Everything the engine carries from one event to the next (the state aside).
  void save(ByteWriter& w) const {
    count_.save(w);
    w.put(loop_);
    w.put(keeper_.skin());
    w.put<std::int32_t>(s_.n_spheres());
    w.put<std::int32_t>(static_cast<std::int32_t>(s_.clusters.size()));
    grid_.save(w);
    lists_.save(w);
    calendar_.save(w);
    keeper_.save(w);
  }

  EventDrivenCounters& counters() { return count_; }
  EventLoopState& loop() { return loop_; }

 private:
  // The members fixed by the settings and the state.
  struct Sized {};
  EventDrivenCore(State<D>& state, const EventDrivenSettings& settings, Sized)
      : s_(state), law_(settings.collision),
        // grid_ is built after keeper_, which keeps only its address.
        keeper_(TranslationDrift<D>(state, &grid_),
                fitted_skin(state, settings.skin.value_or(0.0), default_skin(state, settings.collision.outcome),
                            SkinLimitRounding::divide_first)),
        grid_(state.box, binning_cell_size(state, keeper_.skin()), state.n_spheres()) {
    keep_what_the_law_reads(s_, law_);
  }

  bool valid(const Event& e) const {
    if (e.kind == EventKind::collision) {
      return cluster_of(e.a).stamp == e.stamp_a && cluster_of(e.b).stamp == e.stamp_b;
    }
    return s_.clusters[e.a].stamp == e.stamp_a;
  }

  // ---- neighbour lists -------------------------------------------------------------------

  // Calls found(j) for every foreign sphere j whose bin is within sigma + skin of sphere
  // i's bin, for which wanted(j) holds (neighbor_keeper.hpp).
  template <class Wanted, class Found>
  void for_each_foreign_near(int i, Wanted&& wanted, Found&& found) const {
    ballagg::for_each_foreign_near(
        grid_, s_, keeper_.skin(), s_.spheres.cluster[i], grid_.binned(i), s_.spheres.radius[i], wanted,
        [&](int j) { return s_.spheres.radius[j]; }, found);
  }

  bool bins_within_reach(int i, int j) const {
    return ballagg::bins_within_reach(s_.box, grid_.binned(i), grid_.binned(j), s_.spheres.radius[i],
                                      s_.spheres.radius[j], keeper_.skin());
  }

  // A calendar that keeps every event keeps the predictions already made and files those
  // of the new pairs. One that keeps the earliest only held nothing else of c's: c is
  // predicted afresh. The pairs dropped from the lists are then not predicted again; none
  // of them can touch before one of its two clusters rebuilds (neighbor_keeper.hpp), and
  // that rebuild lists the pair again if it comes within reach.
  EventRecord rebuild(int c, double t) {
    const std::int32_t* cluster = s_.spheres.cluster.data();
    const Cluster<D>& k = s_.clusters[c];
    for (int i : k.members) grid_.move(i, s_.box.wrap(unwrapped_position(i, t)));
    // Drop the pairs now out of reach. Removal swaps the last entry of a list into the
    // hole, so walking each list from its end visits every entry once.
    for (auto e = static_cast<std::ptrdiff_t>(lists_.exposed(c).size()) - 1; e >= 0; --e) {
      const int i = lists_.exposed(c)[e];
      prefetch_bins(i);
      for (auto p = static_cast<std::ptrdiff_t>(lists_.partners(i).size()) - 1; p >= 0; --p) {
        const int j = lists_.partners(i)[p];
        if (!bins_within_reach(i, j)) lists_.remove_pair(i, j, cluster);
      }
    }
    // List (and predict) the pairs that came into reach.
    keeper_.reset(c, t);
    const double expiry = keeper_.renew_expiry(c);
    const bool keeps_every_event = calendar_.keeps() == CalendarKeeps::every_event;
    batch_.clear();
    for (int i : k.members) {
      for_each_foreign_near(i, [&](int j) { return !lists_.listed(i, j); }, [&](int j) {
        lists_.add_pair(i, j, cluster);
        if (!keeps_every_event) return;
        if (auto e = pair_event(i, j)) batch_.push_back(*e);
      });
    }
    if (keeps_every_event) {
      if (expiry < kNever) batch_.push_back({expiry, c, 0, k.stamp, 0, EventKind::list_rebuild});
      calendar_.file(c, batch_);
    } else {
      predict(c);
    }
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
    for (int j : partners) {
      prefetch(&s_.spheres.cluster[j]);
      prefetch(&s_.spheres.offset[j]);
      prefetch(&s_.spheres.radius[j]);
    }
    for (int j : partners) {
      const int d = s_.spheres.cluster[j];
      prefetch(&s_.clusters[d]);
      if (keeps_expiries()) prefetch(keeper_.expiry_address(d));
    }
  }

  // The same for the bins and radii of sphere i's partners, which a list rebuild reads.
  void prefetch_bins(int i) const {
    for (int j : lists_.partners(i)) {
      prefetch(&grid_.binned(j));
      prefetch(&s_.spheres.radius[j]);
    }
  }

  // The contact event of spheres i and j (different clusters), if they approach, and if
  // it can come before `horizon` (the earliest event of a prediction keeping only that).
  // The periodic image walk stops at the earlier list rebuild of the two clusters: a
  // contact through a farther image needs the pair to leave and re-enter the lists first.
  // (Nothing else reads a partner's expiry: a box with walls keeps none.)
  bool keeps_expiries() const { return s_.box.periodic(); }
  std::optional<Event> pair_event(int i, int j, double horizon = kNever) {
    const int a = s_.spheres.cluster[i], b = s_.spheres.cluster[j];
    const double limit = keeps_expiries() ? std::min(keeper_.expiry(a), keeper_.expiry(b)) : kNever;
    const double t =
        predicted_contact(s_.box, s_.clusters[a], s_.spheres.offset[i], s_.clusters[b], s_.spheres.offset[j],
                          s_.spheres.radius[i] + s_.spheres.radius[j], s_.time, limit, horizon);
    ++count_.pair_predictions;
    if (t == kNever) return std::nullopt;
    const int lo = std::min(i, j), hi = std::max(i, j);
    return Event{t, lo, hi, cluster_of(lo).stamp, cluster_of(hi).stamp, EventKind::collision};
  }

  // Files the next wall contact, list rebuild and pair contacts of cluster c, replacing
  // everything filed under c before (all of it involved c's previous motion). A calendar
  // that keeps c's earliest event only needs no contact after the earliest found so far,
  // and the pairs are predicted against it: a contact certainly later costs no root.
  void predict(int c, bool skip_lower_clusters = false, int skip_cluster = -1) {
    const Cluster<D>& k = s_.clusters[c];
    const bool earliest_only = calendar_.keeps() == CalendarKeeps::earliest_only;
    std::optional<Event> earliest;
    batch_.clear();
    const auto take = [&](const Event& e) {
      if (!earliest_only) batch_.push_back(e);
      else if (!earliest || later(*earliest, e)) earliest = e;
    };
    const WallContact w = next_wall_contact(s_, c);
    if (w.time < kNever) take({w.time, c, w.axis, k.stamp, 0, EventKind::wall});
    const double expiry = keeper_.renew_expiry(c);
    if (expiry < kNever) take({expiry, c, 0, k.stamp, 0, EventKind::list_rebuild});
    for (int i : lists_.exposed(c)) {
      prefetch_partners(i);
      for (int j : lists_.partners(i)) {
        const int d = s_.spheres.cluster[j];
        if (d == skip_cluster || (skip_lower_clusters && d < c)) continue;
        if (auto e = pair_event(i, j, earliest ? earliest->time : kNever)) take(*e);
      }
    }
    if (earliest) batch_.push_back(*earliest);
    calendar_.refile(c, batch_);
    count_.queue_peak = std::max<std::int64_t>(count_.queue_peak, calendar_.size());
  }

  // Cluster c's earliest event was stale, and the calendar keeps no other
  // (event_calendar.hpp): its events are predicted again, the same as when they were left
  // out.
  void refill(int c) { predict(c); }

  // ---- event handlers --------------------------------------------------------------------

  EventRecord hit_wall(int c, int axis, double t) {
    keeper_.fold(c, t);
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
      keeper_.fold(a, t);
      keeper_.fold(b, t);
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
    const double slack = std::max(keeper_.drift(a, t), keeper_.drift(b, t));
    const int absorbed = std::min(s_.clusters[a].size(), s_.clusters[b].size());
    const int keep = s_.merge(i, j, t);
    const int gone = keep == a ? b : a;
    const MemberList& members = s_.clusters[keep].members;  // absorbed ones last
    for (auto m = members.end() - absorbed; m != members.end(); ++m) grid_.set_tag(*m, keep);
    lists_.absorb(keep, gone, s_.spheres.cluster.data());
    calendar_.forget(gone);
    keeper_.forget(gone);
    keeper_.restart(keep, slack);
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

  const Cluster<D>& cluster_of(int i) const { return s_.cluster_of(i); }
  Vec<D> unwrapped_position(int i, double t) const { return s_.unwrapped_position(i, t); }

  State<D>& s_;
  CollisionSettings law_;
  NeighborKeeper<TranslationDrift<D>> keeper_;  // the skin, drifts and list expiries
  CellGrid<D> grid_;
  NeighborLists lists_;
  std::vector<Event> batch_;         // scratch for predict() and rebuild()
  EventDrivenCounters count_;
  EventLoopState loop_;
};

}  // namespace

template <int D>
double default_skin(const State<D>& s, CollisionOutcome outcome) {
  // Radius r of the ball holding kSkinNeighbours centres at number density n.
  const double density = s.n_spheres() / s.box.volume();
  const double unit_ball = D == 2 ? std::numbers::pi : 4.0 / 3.0 * std::numbers::pi;
  const double reach = std::pow(kSkinNeighbours / (density * unit_ball), 1.0 / D);
  const double floor = outcome == CollisionOutcome::bounce ? kMinBouncingSkin : kMinSkin;
  return std::max(reach - 2.0 * s.mean_radius(), floor * s.mean_radius());
}

template <int D>
std::unique_ptr<Engine<D>> make_event_driven_engine(const EventDrivenSettings& settings) {
  return std::make_unique<EventLoopEngine<D, EventDrivenCore<D>>>("ed", settings);
}

template double default_skin<2>(const State<2>&, CollisionOutcome);
template double default_skin<3>(const State<3>&, CollisionOutcome);
template std::unique_ptr<Engine<2>> make_event_driven_engine<2>(const EventDrivenSettings&);
template std::unique_ptr<Engine<3>> make_event_driven_engine<3>(const EventDrivenSettings&);

}  // namespace ballagg
