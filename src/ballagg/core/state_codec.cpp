#include "ballagg/core/state_codec.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ballagg/core/byte_stream.hpp"

namespace ballagg {
namespace {

// How far outside the walls a saved sphere may be: up to a box length. A run leaves spheres
// at most a round-off outside (the time-stepping engine a little more, between the
// minimisation that pushed a cluster through a wall and the step that moves it back);
// beyond, a position is no run's, and the cell lists would bin it through an
// out-of-range conversion.
constexpr double kBoxLengthsOutside = 1.0;

// The numbers of a decoded state that no run can produce: not finite, radii and masses not
// positive, caches of the radii that contradict them, spheres far outside the walls. The
// structure (indices, counts) is checked as it is read; these are checked here, once it
// is whole. A state refused here would otherwise reach the engines as NaN positions and
// cell sizes (a checkpoint with a NaN largest radius would make the rigid-body engine's
// cell grid convert NaN to int: tests/fuzz/corpus, Checkpoint.FuzzedStateWithNan...).
template <int D>
void check_numbers(const State<D>& s, const ByteReader& r, std::size_t first_bad_extent) {
  if (!std::isfinite(s.time)) r.fail("time not a finite number");
  double smallest = std::numeric_limits<double>::infinity(), largest = 0.0;
  for (int i = 0; i < s.n_spheres(); ++i) {
    const double radius = s.spheres.radius[i], mass = s.spheres.mass[i];
    if (!(std::isfinite(radius) && radius > 0.0)) r.fail("a sphere radius not a positive number");
    if (!(std::isfinite(mass) && mass > 0.0)) r.fail("a sphere mass not a positive number");
    if (!s.spheres.offset[i].allFinite()) r.fail("a sphere offset not finite");
    smallest = std::min(smallest, radius);
    largest = std::max(largest, radius);
  }
  for (std::size_t c = 0; c < s.clusters.size(); ++c) {
    const Cluster<D>& k = s.clusters[c];
    const ClusterExtent<D> e = s.extent(static_cast<int>(c));
    if (!(k.anchor.allFinite() && k.velocity.allFinite() && std::isfinite(k.anchor_time) && e.lo.allFinite() &&
          e.hi.allFinite() && c != first_bad_extent && !std::isnan(s.last_collision_time(static_cast<int>(c)))))
      r.fail("a cluster's motion or extent not finite");
    if (!(std::isfinite(k.mass) && (k.mass > 0.0 || !k.alive()))) r.fail("a cluster mass not a positive number");
  }
  // The caches may exceed what the radii say (sphere coagulation keeps the running extremes
  // of spheres since removed), never contradict it.
  if (!(std::isfinite(s.max_radius()) && s.max_radius() >= largest)) r.fail("largest radius inconsistent with the radii");
  if (!(std::isfinite(s.min_diameter()) && s.min_diameter() > 0.0 && s.min_diameter() <= 2.0 * smallest))
    r.fail("smallest diameter inconsistent with the radii");
  if (!(std::isfinite(s.mean_radius()) && s.mean_radius() > 0.0)) r.fail("mean radius not a positive number");
  if (!(s.wall_impulse().allFinite() && std::isfinite(s.running_kinetic_energy()) && s.running_momentum().allFinite()))
    r.fail("running totals not finite");
  const double low = -kBoxLengthsOutside * s.box.length, high = (1.0 + kBoxLengthsOutside) * s.box.length;
  for (int i = 0; i < s.n_spheres(); ++i) {
    const Vec<D> x = s.unwrapped_position(i, s.time);
    if (!x.allFinite()) r.fail("a sphere position not finite");
    if (!s.box.periodic() && ((x.array() < low).any() || (x.array() > high).any()))
      r.fail("a sphere more than a box length outside the walls");
  }
}

}  // namespace

template <int D>
std::string StateCodec<D>::encode(const State<D>& s) {
  ByteWriter w;
  encode(s, w);
  return w.take();
}

template <int D>
void StateCodec<D>::encode(const State<D>& s, ByteWriter& w) {
  w.put(s.box.length);
  w.put(static_cast<std::int32_t>(s.box.boundary));
  w.put(s.time);
  w.put_vector(s.spheres.offset);
  w.put_vector(s.spheres.radius);
  w.put_vector(s.spheres.mass);
  w.put_vector(s.spheres.cluster);
  w.put<std::uint64_t>(s.clusters.size());
  for (std::size_t c = 0; c < s.clusters.size(); ++c) {
    const Cluster<D>& k = s.clusters[c];
    w.put(k.anchor);
    w.put(k.velocity);
    w.put(k.anchor_time);
    w.put(k.stamp);
    w.put(k.mass);
    w.put_array(k.members.data(), k.members.size());
    const ClusterExtent<D> e = s.extent(static_cast<int>(c));
    w.put(e.lo);
    w.put(e.hi);
    w.put(s.last_collision_time(static_cast<int>(c)));
  }
  w.put(s.last_stamp_);
  w.put_vector(s.alive_);
  w.put(s.largest_cluster_);
  w.put(s.min_diameter_);
  w.put(s.max_radius_);
  w.put(s.mean_radius_);
  w.put(s.pinnings_);
  w.put(s.wall_impulse_);
  w.put(s.running_energy_);
  w.put(s.running_momentum_);
  w.put(s.resync_below_);
}

template <int D>
State<D> StateCodec<D>::decode(std::string_view bytes) {
  ByteReader r(bytes, "checkpoint state");
  State<D> s;
  s.box.length = r.get<double>("box length");
  const auto boundary = r.get<std::int32_t>("boundary");
  if (boundary != static_cast<std::int32_t>(Boundary::walls) && boundary != static_cast<std::int32_t>(Boundary::periodic))
    r.fail("unknown boundary");
  if (!(std::isfinite(s.box.length) && s.box.length > 0.0)) r.fail("box length not a positive number");
  s.box.boundary = static_cast<Boundary>(boundary);
  s.time = r.get<double>("time");
  s.spheres.offset = r.get_vector<Vec<D>>("sphere offsets");
  const std::uint64_t n = s.spheres.offset.size();
  s.spheres.radius = r.get_vector<double>("sphere radii", n);
  s.spheres.mass = r.get_vector<double>("sphere masses", n);
  s.spheres.cluster = r.get_vector<std::int32_t>("sphere clusters", n);
  if (s.spheres.radius.size() != n || s.spheres.mass.size() != n || s.spheres.cluster.size() != n)
    r.fail("sphere arrays of different lengths");
  const auto m = r.get<std::uint64_t>("cluster count");
  // Not more than spheres, except with sphere coagulation (the rigid-body engine's models
  // i-ii), which removes spheres and keeps the emptied clusters: bounded by the bytes left
  // (every cluster takes at least its fixed fields) before anything is allocated.
  constexpr std::uint64_t kClusterBytes = (4 * D + 5) * sizeof(double);
  if (m > r.remaining() / kClusterBytes) r.fail("more clusters than the bytes left can hold");
  s.clusters.resize(m);
  s.extents_.reset(m);
  std::uint64_t members = 0;
  std::size_t first_bad_extent = m;  // the first cluster saved with an extent not finite
  for (std::size_t c = 0; c < m; ++c) {
    Cluster<D>& k = s.clusters[c];
    k.anchor = r.get<Vec<D>>("cluster anchor");
    k.velocity = r.get<Vec<D>>("cluster velocity");
    k.anchor_time = r.get<double>("cluster anchor time");
    k.stamp = r.get<std::uint64_t>("cluster stamp");
    k.mass = r.get<double>("cluster mass");
    r.get_into<std::int32_t>(k.members, "cluster members", n - members);
    members += k.members.size();
    ClusterExtent<D> e;
    e.lo = r.get<Vec<D>>("cluster extent");
    e.hi = r.get<Vec<D>>("cluster extent");
    // A cluster of one sphere computes its extent from it: what was saved is only checked
    // (with the other numbers, below).
    if (!(e.lo.allFinite() && e.hi.allFinite())) first_bad_extent = std::min(first_bad_extent, c);
    if (k.members.size() > 1) s.store_extent(static_cast<int>(c), e);
    // Collision times are kept only if the saved state kept any (State::keep_collision_times).
    const double collided = r.get<double>("cluster collision time");
    if (collided != State<D>::kNeverCollided) {
      if (s.last_collision_time_.empty()) s.last_collision_time_.assign(m, State<D>::kNeverCollided);
      s.last_collision_time_[c] = collided;
    }
  }
  // Every sphere is a member of exactly the cluster it names.
  if (members != n) r.fail("cluster members do not cover the spheres");
  for (std::size_t c = 0; c < m; ++c)
    for (std::int32_t i : s.clusters[c].members)
      if (i < 0 || static_cast<std::uint64_t>(i) >= n || s.spheres.cluster[i] != static_cast<std::int32_t>(c))
        r.fail("a cluster member that is not a sphere of that cluster");
  s.last_stamp_ = r.get<std::uint64_t>("last stamp");
  // Stamps are handed out in increasing order, so none exceeds the last; kStampLimit bounds
  // them all.
  if (s.last_stamp_ >= kStampLimit) r.fail("last stamp beyond 2^61");
  for (const Cluster<D>& k : s.clusters)
    if (k.stamp > s.last_stamp_) r.fail("a cluster stamp later than the last stamp");
  s.alive_ = r.get_vector<std::int32_t>("live clusters", m);
  s.alive_slot_.assign(m, -1);
  for (std::size_t k = 0; k < s.alive_.size(); ++k) {
    const std::int32_t c = s.alive_[k];
    if (c < 0 || static_cast<std::uint64_t>(c) >= m || s.alive_slot_[c] >= 0 || !s.clusters[c].alive())
      r.fail("live cluster list inconsistent with the clusters");
    s.alive_slot_[c] = static_cast<std::int32_t>(k);
  }
  for (std::size_t c = 0; c < m; ++c)
    if (s.clusters[c].alive() && s.alive_slot_[c] < 0) r.fail("a cluster with members missing from the live list");
  s.largest_cluster_ = r.get<int>("largest cluster");
  s.min_diameter_ = r.get<double>("smallest diameter");
  s.max_radius_ = r.get<double>("largest radius");
  s.mean_radius_ = r.get<double>("mean radius");
  s.pinnings_ = r.get<std::int64_t>("pinnings");
  s.wall_impulse_ = r.get<Vec<D>>("wall impulse");
  s.running_energy_ = r.get<double>("kinetic energy");
  s.running_momentum_ = r.get<Vec<D>>("momentum");
  s.resync_below_ = r.get<int>("resync threshold");
  r.expect_end();
  check_numbers(s, r, first_bad_extent);
  s.layout_changed();
  return s;
}

template struct StateCodec<2>;
template struct StateCodec<3>;

}  // namespace ballagg
