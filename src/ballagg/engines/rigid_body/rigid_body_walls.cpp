// The rigid-body engine at the walls: when a body reaches one, the search on its rotating
// spheres, and the impulse of a wall.
#include "ballagg/engines/rigid_body/rigid_body_core.hpp"

#include "ballagg/collision/rigid_impulse.hpp"

namespace ballagg {

template <int D>
void RigidBodyCore<D>::predict_walls(int c, double now) {
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

template <int D>
void RigidBodyCore<D>::search_wall(int c, int w, double t) {
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

template <int D>
EventRecord RigidBodyCore<D>::hit_wall(int i, int w, double t) {
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

template void RigidBodyCore<2>::predict_walls(int, double);
template void RigidBodyCore<3>::predict_walls(int, double);
template void RigidBodyCore<2>::search_wall(int, int, double);
template void RigidBodyCore<3>::search_wall(int, int, double);
template EventRecord RigidBodyCore<2>::hit_wall(int, int, double);
template EventRecord RigidBodyCore<3>::hit_wall(int, int, double);

}  // namespace ballagg
