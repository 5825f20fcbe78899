// The rigid-body engine's predictions: exact contact times of bodies that only translate,
// conservative advancement (contact_search.hpp) for the others.
#include "ballagg/engines/rigid_body/rigid_body_core.hpp"

#include "ballagg/collision/prediction.hpp"

namespace ballagg {

template <int D>
void RigidBodyCore<D>::predict(int c, bool skip_lower_bodies, int skip_body) {
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

template <int D>
void RigidBodyCore<D>::predict_pairs(int c, double now) {
  for (std::size_t first = 0; first < pairs_.size();) {
    std::size_t last = first;
    while (last < pairs_.size() && pairs_[last][0] == pairs_[first][0]) ++last;
    predict_pair(c, pairs_[first][0], first, last, now);
    first = last;
  }
}

template <int D>
void RigidBodyCore<D>::predict_pair(int c, int d, std::size_t first, std::size_t last, double now) {
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

template <int D>
PairStep RigidBodyCore<D>::advance_pairs(int c, int d, double t) {
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

template <int D>
EventRecord RigidBodyCore<D>::search(int c, int d, double t) {
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

template void RigidBodyCore<2>::predict(int, bool, int);
template void RigidBodyCore<3>::predict(int, bool, int);
template void RigidBodyCore<2>::predict_pairs(int, double);
template void RigidBodyCore<3>::predict_pairs(int, double);
template void RigidBodyCore<2>::predict_pair(int, int, std::size_t, std::size_t, double);
template void RigidBodyCore<3>::predict_pair(int, int, std::size_t, std::size_t, double);
template PairStep RigidBodyCore<2>::advance_pairs(int, int, double);
template PairStep RigidBodyCore<3>::advance_pairs(int, int, double);
template EventRecord RigidBodyCore<2>::search(int, int, double);
template EventRecord RigidBodyCore<3>::search(int, int, double);

}  // namespace ballagg
