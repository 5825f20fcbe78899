#include "ballagg/engines/rigid_body/rigid_bodies.hpp"

#include <algorithm>
#include <cmath>

#include "ballagg/collision/rigid_coagulation.hpp"
#include "ballagg/core/byte_stream.hpp"

namespace ballagg {
namespace {

// The free rotation of a body whose own frame holds the principal axes `principal`; it
// reports the orientation of the own frame.
FreeRotation<3> free_rotation(const Spin<3>& moments, const Rotation<3>& space_from_principal, const Spin<3>& h,
                              double t, const Rotation<3>& principal) {
  return FreeRotation<3>(moments, Eigen::Quaterniond(space_from_principal), h, t, principal);
}
FreeRotation<2> free_rotation(const Spin<2>& moments, const Rotation<2>& space_from_principal, const Spin<2>& h,
                              double t, const Rotation<2>&) {
  return FreeRotation<2>(moments[0], std::atan2(space_from_principal(1, 0), space_from_principal(0, 0)), h, t);
}

// The inverse inertia tensor in the space frame: R diag(1/I) R^T (2D: 1/I).
InertiaTensor<3> inverse_inertia(const Rotation<3>& space_from_principal, const Spin<3>& moments) {
  return space_from_principal * moments.cwiseInverse().asDiagonal() * space_from_principal.transpose();
}
InertiaTensor<2> inverse_inertia(const Rotation<2>&, const Spin<2>& moments) { return moments.cwiseInverse(); }

}  // namespace

template <int D>
void RigidBodies<D>::build(State<D>& s) {
  const double t = s.time;
  body_.assign(s.clusters.size(), Body{});
  coord_.assign(s.n_spheres(), Vec<D>::Zero());
  const bool spinning = !s.spin.empty();
  s.spin.resize(s.clusters.size());
  std::vector<Vec<D>> x;
  std::vector<double> r, m;
  for (int c : s.alive_clusters()) {
    const Cluster<D>& k = s.clusters[c];
    x.clear(), r.clear(), m.clear();
    for (int i : k.members) {
      x.push_back(s.spheres.offset[i]);
      r.push_back(s.spheres.radius[i]);
      m.push_back(s.spheres.mass[i]);
    }
    const MassProperties<D> p = sphere_mass_properties<D>(x, r, m);
    Body& b = body_[c];
    for (std::size_t k2 = 0; k2 < k.members.size(); ++k2) coord_[k.members[k2]] = x[k2] - p.centre;
    b.inertia = p.inertia;
    const PrincipalAxes<D> axes = principal_axes(p.inertia);
    b.principal = axes.axes;
    // The own frame is the space frame now: the spin angular momentum is I omega.
    const Spin<D> omega = spinning ? s.spin[c].angular_velocity : Spin<D>::Zero();
    const Spin<D> h = p.inertia * omega;
    b.rotation = free_rotation(axes.moments, axes.axes, h, t, axes.axes);
    const Vec<D> centre = s.origin(c, t) + p.centre;
    s.set_rigid_motion(c, centre, k.velocity, t);
    s.spin[c].angular_momentum = h;
    refresh_bounds(s, c);
    write_offsets(s, c, t);
  }
}

template <int D>
typename RigidBodies<D>::Pose RigidBodies<D>::pose(int c, double t) const {
  const auto f = body_[c].rotation.at(t);
  return {f.rotation, f.angular_velocity};
}

template <int D>
ImpactBody<D> RigidBodies<D>::impact_body(const State<D>& s, int c, const Pose& p, const Vec<D>& lever) const {
  const Body& b = body_[c];
  const Cluster<D>& k = s.clusters[c];
  ImpactBody<D> out;
  out.inverse_mass = 1.0 / k.mass;
  out.inverse_inertia = inverse_inertia(Rotation<D>(p.rotation * b.principal), b.rotation.moments());
  out.velocity = k.velocity;
  out.angular_velocity = p.angular_velocity;
  out.lever = lever;
  return out;
}

template <int D>
void RigidBodies<D>::set_rotation(State<D>& s, int c, const Rotation<D>& space_from_principal, const Spin<D>& momentum,
                                  double t) {
  Body& b = body_[c];
  b.rotation = free_rotation(b.rotation.moments(), space_from_principal, momentum, t, b.principal);
  s.spin[c] = {b.rotation.at(t).angular_velocity, momentum};
}

template <int D>
void RigidBodies<D>::apply_impulse(State<D>& s, int c, const Vec<D>& impulse, const Vec<D>& lever, double t) {
  const Cluster<D>& k = s.clusters[c];
  const Pose p = pose(c, t);
  const Vec<D> v = k.velocity + impulse / k.mass;
  s.set_rigid_motion(c, s.origin(c, t), v, t);
  set_rotation(s, c, p.rotation * body_[c].principal, body_[c].rotation.angular_momentum() + cross(lever, impulse), t);
}

template <int D>
int RigidBodies<D>::stick(State<D>& s, int i, int j, double t) {
  int a = s.spheres.cluster[i], b = s.spheres.cluster[j];
  if (s.clusters[b].size() > s.clusters[a].size() || (s.clusters[b].size() == s.clusters[a].size() && b < a)) {
    std::swap(a, b);
    std::swap(i, j);
  }
  // a survives; its own frame becomes the joined body's.
  const Pose pa = pose(a, t), pb = pose(b, t);
  const Vec<D> xa = s.origin(a, t);
  const Vec<D> oi = offset(i, a, pa), oj = offset(j, b, pb);
  // b's centre in the periodic image next to a, found through the touching pair.
  const Vec<D> contact = s.box.separation(Vec<D>(s.origin(b, t) + oj), Vec<D>(xa + oi));
  const Vec<D> xb = xa + oi + contact - oj;
  Body& ka = body_[a];
  const Body& kb = body_[b];
  const Rotation<D> to_a = pa.rotation.transpose() * pb.rotation;  // b's own frame -> a's
  const Vec<D> centre_b = pa.rotation.transpose() * (xb - xa) + ka.centre;
  const Vec<D> shift = centre_b - to_a * kb.centre;
  for (int m : s.clusters[b].members) coord_[m] = shift + to_a * coord_[m];

  const MassProperties<D> joined = combined<D>({s.clusters[a].mass, ka.centre, ka.inertia},
                                               {s.clusters[b].mass, centre_b, rotate_tensor(to_a, kb.inertia)});
  const MomentumState<D> momentum = stuck_together<D>(
      {s.clusters[a].mass, xa, s.clusters[a].velocity, ka.rotation.angular_momentum()},
      {s.clusters[b].mass, xb, s.clusters[b].velocity, kb.rotation.angular_momentum()});
  ka.reach = std::max(ka.reach + (ka.centre - joined.centre).norm(), kb.reach + (centre_b - joined.centre).norm());
  ka.radius = std::max(ka.radius + (ka.centre - joined.centre).norm(), kb.radius + (centre_b - joined.centre).norm());
  ka.centre = joined.centre;
  ka.inertia = joined.inertia;
  const PrincipalAxes<D> axes = principal_axes(joined.inertia);
  ka.principal = axes.axes;
  ka.rotation = free_rotation(axes.moments, Rotation<D>(pa.rotation * axes.axes), momentum.spin_momentum, t, axes.axes);
  s.join_rigid(a, b, momentum.centre, momentum.velocity, t);
  s.spin[a] = {ka.rotation.at(t).angular_velocity, momentum.spin_momentum};
  if (ka.reach > kBoundSlack * ka.exact_reach || ka.radius > kBoundSlack * ka.exact_radius) refresh_bounds(s, a);
  body_[b] = Body{};
  return a;
}

template <int D>
int RigidBodies<D>::coalesce(State<D>& s, int i, int j, double r, double speed, double t) {
  const int a = s.spheres.cluster[i], b = s.spheres.cluster[j];
  const Vec<D> xa = s.origin(a, t);
  const Vec<D> xb = xa + s.box.separation(s.origin(b, t), xa);
  MomentumState<D> momentum = stuck_together<D>(
      {s.clusters[a].mass, xa, s.clusters[a].velocity, body_[a].rotation.angular_momentum()},
      {s.clusters[b].mass, xb, s.clusters[b].velocity, body_[b].rotation.angular_momentum()});
  if (speed >= 0.0) {
    // Model (i): every body keeps the initial speed; the direction is the momentum's.
    const double norm = momentum.velocity.norm();
    if (norm > 0.0) momentum.velocity *= speed / norm;
  }
  const int moved = s.coalesce_spheres(i, j, r, momentum.centre, momentum.velocity, t);
  coord_[i].setZero();
  if (moved >= 0) coord_[j] = coord_[moved];
  coord_.pop_back();
  Body& k = body_[a];
  k = Body{};
  k.inertia.diagonal().array() = sphere_moment<D>(s.clusters[a].mass, r);
  k.rotation = free_rotation(Spin<D>(k.inertia.diagonal()), Rotation<D>::Identity(), momentum.spin_momentum, t,
                             Rotation<D>::Identity());
  k.radius = k.exact_radius = r;
  s.spin[a] = {k.rotation.at(t).angular_velocity, momentum.spin_momentum};
  body_[b] = Body{};
  return moved;
}

template <int D>
std::vector<std::int32_t> RigidBodies<D>::fragment(State<D>& s, int c, double released, std::vector<std::int32_t>& empty,
                                                   double t) {
  const Pose p = pose(c, t);
  const Vec<D> centre = s.origin(c, t), velocity = s.clusters[c].velocity;
  const std::vector<std::int32_t> members(s.clusters[c].members.begin(), s.clusters[c].members.end());  // split_rigid changes them
  double spread = 0.0;  // sum m |r|^2 about the centre of mass
  std::vector<Vec<D>> lever(members.size());
  for (std::size_t k = 0; k < members.size(); ++k) {
    lever[k] = offset(members[k], c, p);
    spread += s.spheres.mass[members[k]] * lever[k].squaredNorm();
  }
  const double expansion = spread > 0.0 ? std::sqrt(2.0 * std::max(released, 0.0) / spread) : 0.0;
  write_offsets(s, c, t);
  const std::vector<std::int32_t> taken(empty.end() - (members.size() - 1), empty.end());
  empty.resize(empty.size() - (members.size() - 1));
  const std::vector<std::int32_t> ids = s.split_rigid(c, taken, t);
  for (std::size_t k = 0; k < members.size(); ++k) {
    const int i = members[k], id = ids[k];
    Body& piece = body_[id];
    piece = Body{};
    const double moment = sphere_moment<D>(s.spheres.mass[i], s.spheres.radius[i]);
    piece.inertia.diagonal().array() = moment;
    piece.radius = piece.exact_radius = s.spheres.radius[i];
    coord_[i].setZero();
    // Each sphere keeps the body's spin; its velocity is the rigid one plus H r.
    const Spin<D> h = moment * p.angular_velocity;
    piece.rotation = free_rotation(Spin<D>(piece.inertia.diagonal()), Rotation<D>::Identity(), h, t, Rotation<D>::Identity());
    const Vec<D> v = velocity + cross(p.angular_velocity, lever[k]) + expansion * lever[k];
    s.set_rigid_motion(id, centre + lever[k], v, t);
    s.spin[id] = {p.angular_velocity, h};
  }
  return ids;
}

template <int D>
void RigidBodies<D>::write_offsets(State<D>& s, int c, double t) const {
  const Cluster<D>& k = s.clusters[c];
  s.layout_changed();
  if (k.size() == 1) {
    s.spheres.offset[k.members.front()].setZero();
    s.spin[c].angular_velocity = body_[c].rotation.at(t).angular_velocity;
    return;
  }
  const Pose p = pose(c, t);
  for (int i : k.members) s.spheres.offset[i] = offset(i, c, p);
  s.spin[c].angular_velocity = p.angular_velocity;
}

template <int D>
void RigidBodies<D>::refresh_bounds(const State<D>& s, int c) {
  Body& b = body_[c];
  b.reach = b.radius = 0.0;
  for (int i : s.clusters[c].members) {
    const double r = reach_of(i, c);
    b.reach = std::max(b.reach, r);
    b.radius = std::max(b.radius, r + s.spheres.radius[i]);
  }
  b.exact_reach = b.reach;
  b.exact_radius = b.radius;
}

template <int D>
void RigidBodies<D>::save(ByteWriter& w) const {
  w.put<std::uint64_t>(body_.size());
  for (const Body& b : body_) {
    w.put(b.centre), w.put(b.principal), w.put(b.inertia);
    b.rotation.save(w);
    w.put(b.reach), w.put(b.radius), w.put(b.exact_reach), w.put(b.exact_radius);
  }
  w.put_vector(coord_);
}

template <int D>
void RigidBodies<D>::restore(ByteReader& r, int n_clusters, int n_spheres) {
  if (r.get<std::uint64_t>("body count") != static_cast<std::uint64_t>(n_clusters)) r.fail("bodies for another number of clusters");
  body_.assign(n_clusters, Body{});
  for (Body& b : body_) {
    b.centre = r.get<Vec<D>>("body centre");
    b.principal = r.get<Rotation<D>>("principal axes");
    b.inertia = r.get<InertiaTensor<D>>("inertia tensor");
    b.rotation.restore(r);
    b.reach = r.get<double>("body reach"), b.radius = r.get<double>("body radius");
    b.exact_reach = r.get<double>("body reach"), b.exact_radius = r.get<double>("body radius");
  }
  coord_ = r.get_vector<Vec<D>>("body coordinates", n_spheres);
  if (static_cast<int>(coord_.size()) != n_spheres) r.fail("body coordinates for another number of spheres");
}

template <int D>
double total_kinetic_energy(const State<D>& s) {
  double e = s.kinetic_energy();
  if (s.spin.empty()) return e;
  std::vector<Vec<D>> x;
  std::vector<double> r, m;
  for (int c : s.alive_clusters()) {
    x.clear(), r.clear(), m.clear();
    for (int i : s.clusters[c].members) {
      x.push_back(s.spheres.offset[i]);
      r.push_back(s.spheres.radius[i]);
      m.push_back(s.spheres.mass[i]);
    }
    const Spin<D>& w = s.spin[c].angular_velocity;
    e += 0.5 * w.dot(sphere_mass_properties<D>(x, r, m).inertia * w);
  }
  return e;
}

template double total_kinetic_energy<2>(const State<2>&);
template double total_kinetic_energy<3>(const State<3>&);
template class RigidBodies<2>;
template class RigidBodies<3>;

}  // namespace ballagg
