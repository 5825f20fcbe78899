#include "ballagg/core/state.hpp"

#include <algorithm>
#include <atomic>
#include <limits>

#include "ballagg/core/stick_velocity.hpp"
#include "ballagg/core/tolerances.hpp"

namespace ballagg {

namespace {

// The numbers State::layout_version() draws: never the same twice in a process (states are
// copied, and sweeps run several at once).
std::uint64_t new_layout_version() {
  static std::atomic<std::uint64_t> last{0};
  return last.fetch_add(1, std::memory_order_relaxed) + 1;
}

}  // namespace

template <int D>
std::uint64_t State<D>::layout_version() const {
  if (layout_changed_) {
    layout_version_ = new_layout_version();
    layout_changed_ = false;
  }
  return layout_version_;
}

template <int D>
void State<D>::finalize() {
  layout_changed();
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
  extents_.reset(clusters.size());
  if (!last_collision_time_.empty()) last_collision_time_.resize(clusters.size(), kNeverCollided);
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
  const Cluster<D>& k = clusters[c];
  if (k.size() <= 1) {
    forget_extent(c);
    return;
  }
  ClusterExtent<D> e;
  e.lo = Vec<D>::Constant(std::numeric_limits<double>::infinity());
  e.hi = -e.lo;
  for (int i : k.members) {
    const Vec<D> r = Vec<D>::Constant(spheres.radius[i]);
    e.lo = e.lo.cwiseMin(spheres.offset[i] - r);
    e.hi = e.hi.cwiseMax(spheres.offset[i] + r);
  }
  store_extent(c, e);
}

template <int D>
void State<D>::store_extent(int c, const ClusterExtent<D>& e) {
  extents_.store(static_cast<std::size_t>(c), e);
}

template <int D>
void State<D>::forget_extent(int c) {
  extents_.forget(static_cast<std::size_t>(c));
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
  const ClusterExtent<D> e = extent(c);
  return e.hi[a] - e.lo[a] >= box.length - tolerance::kWallPinGap * min_diameter_;
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
  ClusterExtent<D> joined = extent(a);
  const ClusterExtent<D> absorbed = extent(b);  // before its offsets move
  joined.lo = joined.lo.cwiseMin(absorbed.lo + shift);
  joined.hi = joined.hi.cwiseMax(absorbed.hi + shift);
  for (int m : gone.members) {
    spheres.offset[m] += shift;
    spheres.cluster[m] = a;
  }
  layout_changed();
  const Vec<D> v = stick_velocity(keep.mass, keep.velocity, gone.mass, gone.velocity);
  absorb(a, b, t);
  store_extent(a, joined);
  assign_motion(a, v, t);
  add_to_totals(a, +1.0);
  if (n_clusters() <= resync_below_) resync_totals();
  return a;
}

template <int D>
void State<D>::retire(int c) {
  const std::int32_t moved = alive_.back();
  alive_[alive_slot_[c]] = moved;
  alive_slot_[moved] = alive_slot_[c];
  alive_.pop_back();
  alive_slot_[c] = -1;
}

template <int D>
void State<D>::absorb(int keep, int gone, double t) {
  Cluster<D>& k = clusters[keep];
  Cluster<D>& g = clusters[gone];
  // The survivor keeps the extent it had (a merge then widens it; the rigid-body engine
  // bounds its bodies otherwise), now stored since it has several spheres.
  store_extent(keep, extent(keep));
  forget_extent(gone);
  k.mass += g.mass;
  k.members.append(g.members.begin(), g.members.end());
  set_last_collision_time(keep, t);
  g.members.clear();
  g.mass = 0.0;
  g.velocity.setZero();
  g.stamp = new_stamp();
  if (!spin.empty()) spin[gone] = {};
  retire(gone);
  largest_cluster_ = std::max(largest_cluster_, k.size());
}

template <int D>
void State<D>::set_rigid_motion(int c, const Vec<D>& x, const Vec<D>& v, double t) {
  add_to_totals(c, -1.0);
  place(c, x, v, t);
  add_to_totals(c, +1.0);
}

template <int D>
void State<D>::place(int c, const Vec<D>& x, const Vec<D>& v, double t) {
  Cluster<D>& k = clusters[c];
  k.anchor = x;
  k.anchor_time = t;
  k.velocity = v;
  k.stamp = new_stamp();
}

template <int D>
void State<D>::join_rigid(int keep, int gone, const Vec<D>& x, const Vec<D>& v, double t) {
  add_to_totals(keep, -1.0);
  add_to_totals(gone, -1.0);
  for (int m : clusters[gone].members) spheres.cluster[m] = keep;
  layout_changed();
  absorb(keep, gone, t);
  place(keep, x, v, t);
  add_to_totals(keep, +1.0);
  if (n_clusters() <= resync_below_) resync_totals();
}

template <int D>
int State<D>::coalesce_spheres(int i, int j, double r, const Vec<D>& x, const Vec<D>& v, double t) {
  const int a = spheres.cluster[i], b = spheres.cluster[j];
  const int largest = largest_cluster_;
  join_rigid(a, b, x, v, t);
  largest_cluster_ = std::max(largest, 1);
  spheres.mass[i] += spheres.mass[j];
  spheres.radius[i] = r;
  spheres.offset[i].setZero();
  layout_changed();
  max_radius_ = std::max(max_radius_, r);
  min_diameter_ = std::min(min_diameter_, 2.0 * r);
  // Sphere j leaves; the last sphere takes its id.
  const int last = n_spheres() - 1;
  MemberList& members = clusters[a].members;
  members.erase(std::find(members.begin(), members.end(), j));
  forget_extent(a);  // a single sphere again
  int moved = -1;
  if (j != last) {
    moved = last;
    spheres.offset[j] = spheres.offset[last];
    spheres.radius[j] = spheres.radius[last];
    spheres.mass[j] = spheres.mass[last];
    spheres.cluster[j] = spheres.cluster[last];
    MemberList& holder = clusters[spheres.cluster[j]].members;
    *std::find(holder.begin(), holder.end(), last) = j;
  }
  spheres.offset.pop_back();
  spheres.radius.pop_back();
  spheres.mass.pop_back();
  spheres.cluster.pop_back();
  double spread = 0.0;
  for (double radius : spheres.radius) spread += radius - spheres.radius.front();
  mean_radius_ = spheres.radius.front() + spread / n_spheres();
  return moved;
}

template <int D>
std::vector<std::int32_t> State<D>::split_rigid(int c, const std::vector<std::int32_t>& empty_clusters, double t) {
  const std::vector<std::int32_t> members(clusters[c].members.begin(), clusters[c].members.end());
  layout_changed();
  std::vector<std::int32_t> ids{static_cast<std::int32_t>(c)};
  std::vector<Vec<D>> at(members.size());
  for (std::size_t k = 0; k < members.size(); ++k) at[k] = unwrapped_position(members[k], t);
  add_to_totals(c, -1.0);
  Cluster<D>& first = clusters[c];
  first.members.clear();
  first.members.push_back(members.front());
  first.mass = spheres.mass[members.front()];
  first.velocity.setZero();
  for (std::size_t k = 1; k < members.size(); ++k) {
    const std::int32_t id = empty_clusters[k - 1];
    Cluster<D>& piece = clusters[id];
    piece.members.clear();
    piece.members.push_back(members[k]);
    piece.mass = spheres.mass[members[k]];
    piece.velocity.setZero();
    set_last_collision_time(id, t);
    alive_slot_[id] = static_cast<std::int32_t>(alive_.size());
    alive_.push_back(id);
    spheres.cluster[members[k]] = id;
    ids.push_back(id);
  }
  for (std::size_t k = 0; k < members.size(); ++k) {
    Cluster<D>& piece = clusters[ids[k]];
    spheres.offset[members[k]].setZero();
    piece.anchor = at[k];
    piece.anchor_time = t;
    piece.stamp = new_stamp();
    forget_extent(ids[k]);
  }
  largest_cluster_ = 0;
  for (int a : alive_) largest_cluster_ = std::max(largest_cluster_, clusters[a].size());
  return ids;
}

template <int D>
void State<D>::reserve_clusters(int n) {
  if (static_cast<int>(clusters.size()) >= n) return;
  clusters.resize(n);
  alive_slot_.resize(n, -1);
  extents_.resize(n);
  if (!last_collision_time_.empty()) last_collision_time_.resize(n, kNeverCollided);
  if (!spin.empty()) spin.resize(n);
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
