#pragma once
// The state shared by every engine: spheres (struct of arrays, indexed by sphere id) and
// the rigid clusters they belong to (indexed by cluster id).
//
// Clusters translate without rotating (paper §2), so a sphere's position is its cluster's
// position plus a fixed body-frame offset. Each cluster stores where its body origin was at
// one instant (anchor, anchor_time) and its velocity: positions at any time t are evaluated
// lazily, so a cluster of a million spheres moves, bounces or changes velocity in O(1).
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "ballagg/core/box.hpp"
#include "ballagg/core/member_list.hpp"
#include "ballagg/core/sparse_records.hpp"
#include "ballagg/core/spin.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

// Cluster stamps count up from 1 and stay below 2^61: the event-driven calendar keeps an
// event's kind in the top bits of a stamp's word (engines/event_driven/event_calendar.hpp).
// 2^61 renewals would take a run renewing a billion stamps a second 73 years; a state
// loaded with a stamp at or beyond the limit is refused.
inline constexpr std::uint64_t kStampLimit = std::uint64_t{1} << 61;

template <int D>
struct Spheres {
  std::vector<Vec<D>> offset;          // position relative to the owning cluster's anchor
  std::vector<double> radius;
  std::vector<double> mass;
  std::vector<std::int32_t> cluster;   // owning cluster id

  int size() const { return static_cast<int>(radius.size()); }
};

// Aligned to a cache line so that the hot fields below never straddle two. A 2D record is
// one cache line, a 3D one two (its hot fields fill the first); the fields read only by
// wall contacts and the TC model live in State's per-cluster arrays (ClusterExtent,
// last_collision_time), so that the N records of a gas of monomers cost 64 bytes each in 2D.
template <int D>
struct alignas(64) Cluster {
  // Hot: read by every prediction and validity check; kept within one cache line.
  Vec<D> anchor = Vec<D>::Zero();      // body origin at anchor_time (folded into the box if periodic)
  Vec<D> velocity = Vec<D>::Zero();
  double anchor_time = 0.0;
  std::uint64_t stamp = 0;             // renewed at every change of motion or membership
  // Bookkeeping.
  double mass = 0.0;
  MemberList members;                  // sphere ids, empty once merged into another cluster

  bool alive() const { return !members.empty(); }
  int size() const { return static_cast<int>(members.size()); }
};
static_assert(sizeof(Cluster<2>) == 64 && sizeof(Cluster<3>) == 128);

// The body-frame bounding box of a cluster's spheres, radii included (wall contacts).
template <int D>
struct ClusterExtent {
  Vec<D> lo = Vec<D>::Zero();
  Vec<D> hi = Vec<D>::Zero();
};

// The rotation of a rigid cluster (engine.kind = "rigid-body", docs/rigid_body.md): its
// angular velocity (space frame) and spin angular momentum about its centre of mass.
template <int D>
struct ClusterSpin {
  Spin<D> angular_velocity = Spin<D>::Zero();
  Spin<D> angular_momentum = Spin<D>::Zero();
  double energy() const { return 0.5 * angular_velocity.dot(angular_momentum); }  // eq. (2)
};

template <int D>
struct StateCodec;  // checkpoints: core/state_codec.hpp

template <int D>
class State {
 public:
  Box<D> box;
  Spheres<D> spheres;
  std::vector<Cluster<D>> clusters;
  double time = 0.0;
  // Empty unless clusters rotate (rigid-body engine, or an input file with spin columns);
  // then indexed by cluster id. Engines whose clusters only translate never read it.
  std::vector<ClusterSpin<D>> spin;

  // Call once spheres and clusters are filled: computes extents, stamps and totals.
  void finalize();

  int n_spheres() const { return spheres.size(); }
  int n_clusters() const { return static_cast<int>(alive_.size()); }
  // Ids of the clusters that still have members (in no particular order).
  const std::vector<std::int32_t>& alive_clusters() const { return alive_; }
  int largest_cluster() const { return largest_cluster_; }
  double min_diameter() const { return min_diameter_; }
  double max_radius() const { return max_radius_; }
  double mean_radius() const { return mean_radius_; }

  const Cluster<D>& cluster_of(int sphere) const { return clusters[spheres.cluster[sphere]]; }
  // Cluster c's body-frame bounding box; finalize, merges and refresh_extent keep it. Only
  // clusters of several spheres store theirs: a single sphere's is computed from it, so a
  // gas of monomers pays 4 bytes per cluster for extents, not 2 D doubles.
  ClusterExtent<D> extent(int c) const {
    if (const ClusterExtent<D>* stored = extents_.find(c)) return *stored;
    return single_sphere_extent(c);
  }
  // When cluster c last collided (kNeverCollided before): the TC model's memory. Kept only
  // once keep_collision_times() is called (by an engine whose law has tc_time > 0): a run
  // that never bounces pays nothing for it.
  double last_collision_time(int c) const {
    return last_collision_time_.empty() ? kNeverCollided : last_collision_time_[c];
  }
  void set_last_collision_time(int c, double t) {
    if (!last_collision_time_.empty()) last_collision_time_[c] = t;
  }
  void keep_collision_times() {
    if (last_collision_time_.empty()) last_collision_time_.assign(clusters.size(), kNeverCollided);
  }
  static constexpr double kNeverCollided = -1e300;

  // Where the body origin of cluster c is at time t, not folded into the box.
  Vec<D> origin(int c, double t) const {
    const Cluster<D>& k = clusters[c];
    return k.anchor + (t - k.anchor_time) * k.velocity;
  }
  // Sphere centre at time t, not folded into the box (differences need box.separation).
  Vec<D> unwrapped_position(int i, double t) const {
    return origin(spheres.cluster[i], t) + spheres.offset[i];
  }
  Vec<D> position(int i, double t) const { return box.wrap(unwrapped_position(i, t)); }
  const Vec<D>& velocity(int i) const { return cluster_of(i).velocity; }

  // Gives cluster c velocity v from time t on (re-anchors it at t). A component along an
  // axis where the cluster spans the whole box is set to zero (wall pinning, docs/model.md).
  void set_velocity(int c, const Vec<D>& v, double t);
  // The same for a change of velocity by a wall (a reflection, rule 2.2): the momentum it
  // transfers is added to wall_impulse().
  void set_velocity_at_wall(int c, const Vec<D>& v, double t) {
    wall_impulse_ -= clusters[c].mass * clusters[c].velocity;
    set_velocity(c, v, t);
    wall_impulse_ += clusters[c].mass * clusters[c].velocity;
  }

  // Merges the clusters of the touching spheres i and j at time t into one rigid cluster
  // moving with the mass-weighted mean velocity (rule 2.9). The larger cluster (the one
  // with the lower id on a tie) survives and is returned; the other is left empty. The
  // absorbed spheres are appended to the survivor's members.
  int merge(int i, int j, double t);

  // Moves cluster c rigidly by du at time t (time stepping: wall mirroring, minimisation).
  void translate(int c, const Vec<D>& du, double t);
  // Moves sphere i by du within its cluster (time stepping, non-rigid models). Call
  // refresh_extent on its cluster after moving its spheres.
  void displace_sphere(int i, const Vec<D>& du) {
    spheres.offset[i] += du;
    layout_changed();
  }
  void refresh_extent(int c);

  // The sphere layout: spheres.offset and spheres.cluster. Its version is a number that
  // no other layout of any state has had in this process: two calls that return the same
  // value saw the same offsets and cluster ids (trajectory frames then share one copy of
  // them, run/snapshots.hpp). The methods of State call layout_changed() whenever they
  // change an offset or a cluster id; code that writes spheres.offset or spheres.cluster
  // itself must call it too (the rigid-body engine's rotations).
  void layout_changed() { layout_changed_ = true; }
  std::uint64_t layout_version() const;

  // True when cluster c spans the box along axis a (walls only): it cannot move along a.
  bool pinned(int c, int a) const;

  // Totals kept up to date at every change: O(1) to read, within a few ulps of the exact
  // sums (they are recomputed from scratch each time the number of clusters halves).
  double running_kinetic_energy() const { return running_energy_; }
  const Vec<D>& running_momentum() const { return running_momentum_; }

  // Totals computed from scratch (exact up to summation round-off).
  double kinetic_energy() const;
  Vec<D> momentum() const;
  double total_mass() const;
  // Sum of m_i |V_i|: the scale against which momentum errors are measured.
  double momentum_scale() const;

  // Number of times a velocity component was zeroed by wall pinning.
  std::int64_t pinnings() const { return pinnings_; }
  // Total momentum the walls have given the clusters (reflections and pinnings): with
  // walls, momentum() changes by exactly this (up to round-off); periodic boxes keep 0.
  const Vec<D>& wall_impulse() const { return wall_impulse_; }
  // Adds the impulse p a wall gave a cluster whose motion the caller changed itself (the
  // rigid-body engine's wall contacts, which also change the spin).
  void add_wall_impulse(const Vec<D>& p) { wall_impulse_ += p; }

  // ---- rotating rigid bodies (rigid-body engine) ------------------------------------------
  // There a cluster's anchor is its centre of mass, not folded into a periodic box (the
  // engine keeps the unwrapped trajectory), and its offsets are the spheres' positions
  // relative to it at the last time the engine wrote them (it rotates them itself).

  // Cluster c moves with velocity v from centre x at time t (no wall pinning).
  void set_rigid_motion(int c, const Vec<D>& x, const Vec<D>& v, double t);
  // The spheres of cluster `gone` join cluster `keep`, which from time t moves with
  // velocity v from centre x; offsets are left to the caller. O(size of gone).
  void join_rigid(int keep, int gone, const Vec<D>& x, const Vec<D>& v, double t);
  // The single spheres i and j (each a cluster of its own) become one sphere, i, of
  // radius r and mass m_i + m_j moving with v from x at time t. Sphere j is removed: the
  // last sphere takes its id. Returns the old id of the sphere now numbered j (-1 if j
  // was the last).
  int coalesce_spheres(int i, int j, double r, const Vec<D>& x, const Vec<D>& v, double t);
  // Every sphere of cluster c but its first moves to a cluster of its own, taken from
  // `empty_clusters` in order (they must have no members), at rest at its position at
  // time t (offsets must be current). Returns the ids, first sphere's (c) first.
  std::vector<std::int32_t> split_rigid(int c, const std::vector<std::int32_t>& empty_clusters, double t);
  // Appends empty clusters until there are at least n.
  void reserve_clusters(int n);

 private:
  friend struct StateCodec<D>;  // saves and restores the bookkeeping below exactly
  std::uint64_t new_stamp() {
    if (last_stamp_ + 1 >= kStampLimit) throw std::length_error("cluster stamps exhausted (2^61)");
    return ++last_stamp_;
  }
  void assign_motion(int c, const Vec<D>& v, double t);
  void add_to_totals(int c, double sign) {
    const Cluster<D>& k = clusters[c];
    running_energy_ += sign * 0.5 * k.mass * k.velocity.squaredNorm();
    running_momentum_ += sign * k.mass * k.velocity;
  }
  void resync_totals() {
    running_energy_ = kinetic_energy();
    running_momentum_ = momentum();
    resync_below_ = n_clusters() / 2;
  }
  // Removes the (now empty) cluster c from the list of live clusters.
  void retire(int c);
  // Moves the members and mass of cluster `gone` (already relabelled to `keep`) into
  // `keep`, empties and retires `gone`. Motion and totals are the caller's.
  void absorb(int keep, int gone, double t);
  // Cluster c's body origin is at x at time t, moving at v (totals are the caller's).
  void place(int c, const Vec<D>& x, const Vec<D>& v, double t);
  // The extent of a cluster of one sphere (of none: empty, at the origin).
  ClusterExtent<D> single_sphere_extent(int c) const {
    const MemberList& members = clusters[c].members;
    if (members.empty()) return {};
    const int i = members.front();
    const Vec<D> r = Vec<D>::Constant(spheres.radius[i]);
    return {spheres.offset[i] - r, spheres.offset[i] + r};
  }
  // Stores e as cluster c's extent (a cluster of several spheres), or forgets what c stored
  // (one sphere or none: extent() computes it).
  void store_extent(int c, const ClusterExtent<D>& e);
  void forget_extent(int c);

  std::uint64_t last_stamp_ = 0;
  // Indexed by cluster id like `clusters`, and as long (finalize, reserve_clusters): read
  // only by wall contacts and the TC model, so kept out of the cluster records. Only
  // clusters of several spheres store an extent.
  SparseRecords<ClusterExtent<D>> extents_;
  std::vector<double> last_collision_time_;  // empty unless kept
  std::vector<std::int32_t> alive_;       // ids of clusters with members
  std::vector<std::int32_t> alive_slot_;  // position of each cluster id in alive_
  int largest_cluster_ = 0;
  double min_diameter_ = 0.0;
  double max_radius_ = 0.0;
  double mean_radius_ = 0.0;
  std::int64_t pinnings_ = 0;
  Vec<D> wall_impulse_ = Vec<D>::Zero();
  double running_energy_ = 0.0;
  Vec<D> running_momentum_ = Vec<D>::Zero();
  int resync_below_ = 0;
  // layout_version() draws a new number on its first call after a change (lazily, so
  // that a change costs a store: displace_sphere runs for every sphere of a step).
  mutable std::uint64_t layout_version_ = 0;
  mutable bool layout_changed_ = true;
};

extern template class State<2>;
extern template class State<3>;

}  // namespace ballagg
