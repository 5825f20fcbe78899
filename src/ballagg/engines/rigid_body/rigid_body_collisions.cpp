// The rigid-body engine's collisions: bounce (13)-(28), stick (8)-(12) with the contact
// cascade, sphere coalescence (models i-ii) and catastrophic breakup (§2.6).
#include "ballagg/engines/rigid_body/rigid_body_core.hpp"

#include "ballagg/collision/rigid_impulse.hpp"

namespace ballagg {

// A collision may change the kinetic energy by this fraction of the two bodies' kinetic
// energy (round-off) and still count as not creating energy.
constexpr double kEnergyRoundOff = 1e-10;

template <int D>
EventRecord RigidBodyCore<D>::collide(int i, int j, double t) {
  ++count_.collisions;
  EventRecord r{.time = t, .kind = EventKind::collision, .sphere_i = i, .sphere_j = j};
  const int c = body_of(i), d = body_of(j);
  if (!(partner_[c] == serial_[d] && partner_[d] == serial_[c])) ++count_.first_time_collisions;
  partner_[c] = serial_[d];
  partner_[d] = serial_[c];
  const double energy = impact_energy(c, d);
  const RigidBodyLaw& law = settings_.law;
  const CollisionOutcome outcome = settings_.collision.outcome;
  const bool aggregate = law.coagulation == Coagulation::aggregate;
  const bool breaks = aggregate && energy >= law.fragmentation_energy.value_or(kNever) &&
                      (s_.clusters[c].size() > 1 || s_.clusters[d].size() > 1);
  const bool sticks = breaks || outcome == CollisionOutcome::stick ||
                      (outcome == CollisionOutcome::energy_threshold && energy < law.energy_threshold.value_or(kNever));
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

template <int D>
void RigidBodyCore<D>::bounce(int i, int j, double t) {
  const int c = body_of(i), d = body_of(j);
  const Pose pc = pose(c, t), pd = pose(d, t);
  const Vec<D> oi = offset(i, t), oj = offset(j, t);
  const Vec<D> xi = s_.origin(c, t) + oi;
  const Vec<D> n = s_.box.separation(Vec<D>(s_.origin(d, t) + oj), xi).normalized();  // from i to j
  const Vec<D> lever_c = oi + s_.spheres.radius[i] * n, lever_d = oj - s_.spheres.radius[j] * n;
  const ImpactBody<D> bc = bodies_.impact_body(s_, c, pc, lever_c), bd = bodies_.impact_body(s_, d, pd, lever_d);
  const bool recent = t - s_.last_collision_time(c) < settings_.collision.tc() ||
                      t - s_.last_collision_time(d) < settings_.collision.tc();
  const double un = (bd.contact_velocity() - bc.contact_velocity()).dot(n);
  const RigidBodyLaw& law = settings_.law;
  ImpactCoefficients k{settings_.collision.restitution, law.mu_t, law.mu_p};
  if (law.restitution_law == RestitutionLaw::bridges)
    k.normal_restitution = bridges_restitution(std::abs(un) * law.velocity_unit);
  if (recent) k.normal_restitution = 1.0;
  const Impact<D> impact = collision_impulse(bc, bd, n, k);
  ++count_.bounces;
  if (impact.approaching) {
    const double scale = bodies_.kinetic_energy(s_, c) + bodies_.kinetic_energy(s_, d);
    if (!(impact.denominator > 0.0) || impact.energy_change > kEnergyRoundOff * scale) {
      throw InputError(fmt::format(
          "collision.mu_t = {}, collision.mu_p = {}: at t = {} the collision of spheres {} and {} would {} (the "
          "generalised coefficients must not create energy, Brach 1994); use smaller transverse coefficients",
          law.mu_t, law.mu_p, t, i, j,
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
  s_.set_last_collision_time(c, t);
  s_.set_last_collision_time(d, t);
  // Both motions changed: c's predictions must see d's new list expiry.
  keeper_.renew_expiry(d);
  predict(c);
  predict(d, false, c);
}

template <int D>
int RigidBodyCore<D>::stick(int i, int j, double t) {
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
  const MemberList& members = s_.clusters[keep].members;  // absorbed ones last
  for (auto m = members.end() - absorbed; m != members.end(); ++m) grid_->set_tag(*m, keep);
  lists_.absorb(keep, gone, cluster);
  calendar_.forget(gone);
  keeper_.restart(keep, slack);
  forget_pose(keep);
  forget_pose(gone);
  for (auto m = members.end() - absorbed; m != members.end(); ++m) {
    const int k = *m;
    grid_->move(k, s_.box.wrap(unwrapped_position(k, t)));
    drop_out_of_reach(k);
    for_each_foreign_near(k, [&](int j2) { return !lists_.listed(k, j2); }, [&](int j2) { lists_.add_pair(k, j2, cluster); });
  }
  forget_pose(keep);
  forget_pose(gone);
  serial_[keep] = next_serial_++;
  partner_[keep] = -1;
  empty_.push_back(gone);
  ++count_.merges;
  return keep;
}

template <int D>
std::optional<std::pair<int, int>> RigidBodyCore<D>::touching_pair(int c, double t) {
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

template <int D>
void RigidBodyCore<D>::check_span(int c) {
  if (!s_.box.periodic()) return;
  const double limit = 0.5 * (s_.box.length - keeper_.skin());
  auto too_big = [&](int b) { return bodies_[b].radius >= limit; };
  if (c >= 0) spans_box_ = spans_box_ || too_big(c);
  else for (int b : s_.alive_clusters()) spans_box_ = spans_box_ || too_big(b);
}

template <int D>
int RigidBodyCore<D>::coalesce(int i, int j, double t, int& merges) {
  renumbered_.clear();
  int merged = std::min(i, j);
  int keep = merge_spheres(i, j, t);
  ++merges;
  // A grown sphere may overlap its neighbours: they join it at once.
  for (int p = sphere_touching(merged, t); p >= 0; p = sphere_touching(merged, t)) {
    keep = merge_spheres(merged, p, t);
    merged = std::min(merged, p);
    ++merges;
  }
  if (s_.max_radius() > grid_radius_) {
    build_spatial();
    return keep;
  }
  std::sort(renumbered_.begin(), renumbered_.end());
  renumbered_.erase(std::unique(renumbered_.begin(), renumbered_.end()), renumbered_.end());
  for (int b : renumbered_)
    if (b != keep && s_.clusters[b].alive()) predict(b);
  predict(keep);
  return keep;
}

template <int D>
int RigidBodyCore<D>::merge_spheres(int i, int j, double t) {
  const double r0 = s_.spheres.radius[i], r1 = s_.spheres.radius[j];
  const double radius = settings_.law.merged_radius == MergedRadius::fixed ? r0 : std::cbrt(r0 * r0 * r0 + r1 * r1 * r1);
  for (int sphere : {i, j})
    if (!merged_sphere_[sphere]) free_mass_ -= s_.spheres.mass[sphere];
  const int lo = std::min(i, j), hi = std::max(i, j), last = s_.n_spheres() - 1;
  const int keep = body_of(lo), gone = body_of(hi);
  detach_sphere(lo);
  detach_sphere(hi);
  if (last != hi) detach_sphere(last);
  const int moved = bodies_.coalesce(s_, lo, hi, radius, settings_.merged_speed(), t);
  merged_sphere_[lo] = 1;
  if (moved >= 0) merged_sphere_[hi] = merged_sphere_[moved];
  merged_sphere_.pop_back();
  grid_->pop_back();
  lists_.pop_back();
  calendar_.forget(gone);
  keeper_.reset(keep, t);
  forget_pose(keep);
  forget_pose(gone);
  attach_sphere(lo, t);
  if (moved >= 0) {
    attach_sphere(hi, t);
    renumbered_.push_back(body_of(hi));
  }
  empty_.push_back(gone);
  ++count_.merges;
  serial_[keep] = next_serial_++;
  partner_[keep] = -1;
  return keep;
}

template <int D>
int RigidBodyCore<D>::sphere_touching(int i, double t) {
  const int c = body_of(i);
  const Vec<D> xi = unwrapped_position(i, t);
  int touching = -1;
  // The grid's cells are at least 2 grid_radius_ + a skin wide: every sphere that can
  // touch i is binned in a cell next to i's.
  grid_->for_each_near_image(s_.box.wrap(xi), c, [&](int p, const Vec<D>&) {
    if (touching >= 0 && p > touching) return;
    const double sigma = (s_.spheres.radius[i] + s_.spheres.radius[p]) * (1.0 + tolerance::kContact);
    if (s_.box.separation(xi, unwrapped_position(p, t)).squaredNorm() <= sigma * sigma) touching = p;
  });
  return touching;
}

template <int D>
void RigidBodyCore<D>::detach_sphere(int i) {
  lists_.remove_all_pairs(i, s_.spheres.cluster.data());
  grid_->remove(i);
}

template <int D>
void RigidBodyCore<D>::attach_sphere(int i, double t) {
  grid_->set_tag(i, body_of(i));
  grid_->insert(i, s_.box.wrap(unwrapped_position(i, t)));
  const std::int32_t* cluster = s_.spheres.cluster.data();
  for_each_foreign_near(i, [&](int j) { return !lists_.listed(i, j); }, [&](int j) { lists_.add_pair(i, j, cluster); });
}

template <int D>
void RigidBodyCore<D>::fragment(int c, double released, double t) {
  const std::int32_t* cluster = s_.spheres.cluster.data();
  const std::vector<std::int32_t> members(s_.clusters[c].members.begin(), s_.clusters[c].members.end());
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
    for_each_foreign_near(i, [&](int j) { return !lists_.listed(i, j); }, [&](int j) { lists_.add_pair(i, j, cluster); });
  for (int b : pieces) keeper_.renew_expiry(b);  // each piece's predictions see the others'
  for (int b : pieces) predict(b);
}

template EventRecord RigidBodyCore<2>::collide(int, int, double);
template EventRecord RigidBodyCore<3>::collide(int, int, double);
template void RigidBodyCore<2>::bounce(int, int, double);
template void RigidBodyCore<3>::bounce(int, int, double);
template int RigidBodyCore<2>::stick(int, int, double);
template int RigidBodyCore<3>::stick(int, int, double);
template std::optional<std::pair<int, int>> RigidBodyCore<2>::touching_pair(int, double);
template std::optional<std::pair<int, int>> RigidBodyCore<3>::touching_pair(int, double);
template void RigidBodyCore<2>::check_span(int);
template void RigidBodyCore<3>::check_span(int);
template int RigidBodyCore<2>::coalesce(int, int, double, int&);
template int RigidBodyCore<3>::coalesce(int, int, double, int&);
template int RigidBodyCore<2>::merge_spheres(int, int, double);
template int RigidBodyCore<3>::merge_spheres(int, int, double);
template int RigidBodyCore<2>::sphere_touching(int, double);
template int RigidBodyCore<3>::sphere_touching(int, double);
template void RigidBodyCore<2>::detach_sphere(int);
template void RigidBodyCore<3>::detach_sphere(int);
template void RigidBodyCore<2>::attach_sphere(int, double);
template void RigidBodyCore<3>::attach_sphere(int, double);
template void RigidBodyCore<2>::fragment(int, double, double);
template void RigidBodyCore<3>::fragment(int, double, double);

}  // namespace ballagg
