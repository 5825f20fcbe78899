#include "ballagg/core/state.hpp"

#include <algorithm>
#include <limits>

#include "ballagg/collision/laws.hpp"
#include "ballagg/core/tolerances.hpp"

namespace ballagg {

template <int D>
void State<D>::finalize() {
  min_diameter_ = std::numeric_limits<double>::infinity();
  max_radius_ = 0.0;
  // Mean as r_0 + mean(r_i - r_0): exactly r_0 when all radii are equal.
  double spread = 0.0;
  for (double r : spheres.radius) {
    min_diameter_ = std::min(min_diameter_, 2.0 * r);
    max_radius_ = std::max(max_radius_, r);
    spread += r - spheres.radius.front();
  }
  mean_radius_ = spheres.radius.empty() ? 0.0 : spheres.radius.front() + spread / n_spheres();
  alive_.clear();
  alive_slot_.assign(clusters.size(), -1);
  largest_cluster_ = 0;
  for (int c = 0; c < static_cast<int>(clusters.size()); ++c) {
    Cluster<D>& k = clusters[c];
    if (!k.alive()) continue;
    alive_slot_[c] = static_cast<std::int32_t>(alive_.size());
    alive_.push_back(c);
    largest_cluster_ = std::max(largest_cluster_, k.size());
    k.mass = 0.0;
    for (int i : k.members) k.mass += spheres.mass[i];
    refresh_extent(c);
    assign_motion(c, k.velocity, k.anchor_time);
  }
  resync_totals();
}

template <int D>
void State<D>::refresh_extent(int c) {
  Cluster<D>& k = clusters[c];
  k.lo = Vec<D>::Constant(std::numeric_limits<double>::infinity());
  k.hi = -k.lo;
  for (int i : k.members) {
    const Vec<D> r = Vec<D>::Constant(spheres.radius[i]);
    k.lo = k.lo.cwiseMin(spheres.offset[i] - r);
    k.hi = k.hi.cwiseMax(spheres.offset[i] + r);
  }
}

template <int D>
void State<D>::translate(int c, const Vec<D>& du, double t) {
  Cluster<D>& k = clusters[c];
  k.anchor = box.wrap(origin(c, t) + du);
  k.anchor_time = t;
  k.stamp = new_stamp();
}

template <int D>
bool State<D>::pinned(int c, int a) const {
  if (box.periodic()) return false;
  const Cluster<D>& k = clusters[c];
  return k.hi[a] - k.lo[a] >= box.length - tolerance::kWallPinGap * min_diameter_;
}

template <int D>
void State<D>::set_velocity(int c, const Vec<D>& v, double t) {
  add_to_totals(c, -1.0);
  assign_motion(c, v, t);
  add_to_totals(c, +1.0);
}

template <int D>
void State<D>::assign_motion(int c, const Vec<D>& v, double t) {
  Cluster<D>& k = clusters[c];
  k.anchor = box.wrap(origin(c, t));
  k.anchor_time = t;
  k.velocity = v;
  for (int a = 0; a < D; ++a) {
    if (k.velocity[a] != 0.0 && pinned(c, a)) {
      wall_impulse_[a] -= k.mass * k.velocity[a];  // the walls hold the cluster
      k.velocity[a] = 0.0;
      ++pinnings_;
    }
  }
  k.stamp = new_stamp();
}

template <int D>
int State<D>::merge(int i, int j, double t) {
  int a = spheres.cluster[i], b = spheres.cluster[j];
  if (clusters[b].size() > clusters[a].size() || (clusters[b].size() == clusters[a].size() && b < a)) {
    std::swap(a, b);
    std::swap(i, j);
  }
  // a survives; i is its sphere of the contact, j the absorbed cluster's sphere.
  add_to_totals(a, -1.0);
  add_to_totals(b, -1.0);
  Cluster<D>& keep = clusters[a];
  Cluster<D>& gone = clusters[b];
  // Offsets of the absorbed spheres in the survivor's frame: the contact vector between
  // the touching spheres is short, so its minimum image is the true one even when the
  // clusters themselves are larger than half the box.
  const Vec<D> contact = box.separation(unwrapped_position(j, t), unwrapped_position(i, t));
  const Vec<D> shift = spheres.offset[i] + contact - spheres.offset[j];
  for (int m : gone.members) {
    spheres.offset[m] += shift;
    spheres.cluster[m] = a;
  }
  keep.lo = keep.lo.cwiseMin(gone.lo + shift);
  keep.hi = keep.hi.cwiseMax(gone.hi + shift);
  const Vec<D> v = stick_velocity(keep.mass, keep.velocity, gone.mass, gone.velocity);
  keep.mass += gone.mass;
  keep.members.insert(keep.members.end(), gone.members.begin(), gone.members.end());
  keep.last_collision_time = t;
  gone.members.clear();
  gone.members.shrink_to_fit();
  gone.mass = 0.0;
  gone.velocity.setZero();
  gone.stamp = new_stamp();
  const std::int32_t moved = alive_.back();
  alive_[alive_slot_[b]] = moved;
  alive_slot_[moved] = alive_slot_[b];
  alive_.pop_back();
  alive_slot_[b] = -1;
  largest_cluster_ = std::max(largest_cluster_, keep.size());
  assign_motion(a, v, t);
  add_to_totals(a, +1.0);
  if (n_clusters() <= resync_below_) resync_totals();
  return a;
}

template <int D>
double State<D>::kinetic_energy() const {
  double e = 0.0;
  for (int c : alive_) e += 0.5 * clusters[c].mass * clusters[c].velocity.squaredNorm();
  return e;
}

template <int D>
Vec<D> State<D>::momentum() const {
  Vec<D> p = Vec<D>::Zero();
  for (int c : alive_) p += clusters[c].mass * clusters[c].velocity;
  return p;
}

template <int D>
double State<D>::total_mass() const {
  double m = 0.0;
  for (double mi : spheres.mass) m += mi;
  return m;
}

template <int D>
double State<D>::momentum_scale() const {
  double s = 0.0;
  for (int c : alive_) s += clusters[c].mass * clusters[c].velocity.norm();
  return s;
}

template class State<2>;
template class State<3>;

}  // namespace ballagg
