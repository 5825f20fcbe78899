#pragma once
// The rigid bodies of the rigid-body engine, one per cluster of the state: each keeps its
// mass properties (centre of mass, inertia tensor (1), principal axes), its torque-free
// rotation since its last collision, and the position of each member sphere in the body's
// own frame (Richardson 1995 §2.1.3: "the position of the sphere center in body
// coordinates").
//
// The own frame is fixed in the body. When two bodies stick, the smaller one's spheres are
// re-expressed in the larger one's frame, O(smaller); the centre of mass and the inertia
// tensor within that frame are updated in O(1) by the parallel-axis theorem. A sphere at
// own-frame coordinate b of body c is at
//   x(t) = X_c(t) + R_c(t) (b - centre_c),      R_c(t) = F_c(t) P_c^T,
// with X_c the centre of mass (the state's cluster anchor: a straight line between
// collisions), F_c the free rotation (space <- principal frame) and P_c the principal axes
// in the own frame. The state's sphere offsets are written from this on request
// (write_offsets).
#include <cstdint>
#include <vector>

#include "ballagg/collision/rigid_impulse.hpp"
#include "ballagg/core/inertia.hpp"
#include "ballagg/core/state.hpp"
#include "ballagg/engines/rigid_body/free_rotation.hpp"

namespace ballagg {

class ByteWriter;
class ByteReader;

// A body's reach and radius bounds are loosened at each merge (triangle inequality); they
// are recomputed exactly, O(size), once they exceed the last exact value by this factor.
inline constexpr double kBoundSlack = 1.1;

template <int D>
class RigidBodies {
 public:
  struct Body {
    Vec<D> centre = Vec<D>::Zero();                       // centre of mass, own frame
    Rotation<D> principal = Rotation<D>::Identity();      // own frame <- principal frame
    InertiaTensor<D> inertia = InertiaTensor<D>::Zero();  // about the centre, own frame
    FreeRotation<D> rotation;                             // space <- principal frame
    double reach = 0.0;        // >= max |b - centre| over the spheres (0 for one sphere)
    double radius = 0.0;       // >= R_max (7) = max (|b - centre| + R)
    double exact_reach = 0.0;  // the exact reach when last computed
    double exact_radius = 0.0;
  };
  // The body's own frame at one instant: x = X + rotation (b - centre).
  struct Pose {
    Rotation<D> rotation = Rotation<D>::Identity();
    Spin<D> angular_velocity = Spin<D>::Zero();
  };

  // One body per live cluster of s, at s.time, spinning as s.spin says (at rest if it is
  // empty). Re-anchors every cluster at its centre of mass and sizes s.spin.
  void build(State<D>& s);

  const Body& operator[](int c) const { return body_[c]; }
  const Vec<D>& coordinate(int sphere) const { return coord_[sphere]; }

  Pose pose(int c, double t) const;
  // Sphere i of body c relative to the centre of mass, with the body at pose p.
  Vec<D> offset(int i, int c, const Pose& p) const { return p.rotation * (coord_[i] - body_[c].centre); }
  // Distance of sphere i's centre from its body's centre of mass (constant in the body).
  double reach_of(int i, int c) const { return (coord_[i] - body_[c].centre).norm(); }
  // True when the body's spheres only translate: one sphere (at the centre), or no spin.
  bool translates(const State<D>& s, int c) const {
    return s.clusters[c].size() == 1 || !body_[c].rotation.rotating();
  }
  // The body as the impulse law sees it at pose p, with the contact at `lever`.
  ImpactBody<D> impact_body(const State<D>& s, int c, const Pose& p, const Vec<D>& lever) const;

  // Impulse P on body c at `lever` from its centre at time t (13)-(14).
  void apply_impulse(State<D>& s, int c, const Vec<D>& impulse, const Vec<D>& lever, double t);
  // Bodies of the touching spheres i and j stick at time t (8)-(12); the larger survives
  // (the lower id on a tie), as in State::merge. Returns the survivor.
  int stick(State<D>& s, int i, int j, double t);
  // The single spheres i and j become one sphere of radius r at their centre of mass
  // (test models (i)-(ii)); speed >= 0 replaces the momentum-conserving speed. Returns the
  // old id of the sphere renumbered j, as State::coalesce_spheres.
  int coalesce(State<D>& s, int i, int j, double r, double speed, double t);
  // Catastrophic breakup (§2.6) of body c at time t: each sphere flies off with the
  // velocity it had in the rigid body plus a radial velocity H r that gives back
  // `released` kinetic energy (momentum and angular momentum are unchanged). Empty
  // cluster ids are taken from `empty` (one per sphere but the first). Returns the bodies.
  std::vector<std::int32_t> fragment(State<D>& s, int c, double released, std::vector<std::int32_t>& empty, double t);

  // Writes the sphere offsets and the angular velocity of body c at time t into the state.
  void write_offsets(State<D>& s, int c, double t) const;
  // Kinetic energy of body c: translation and rotation (eq. 2).
  double kinetic_energy(const State<D>& s, int c) const {
    const Cluster<D>& k = s.clusters[c];
    return 0.5 * k.mass * k.velocity.squaredNorm() + body_[c].rotation.energy();
  }

  // Checkpoints: every body (mass properties, bounds, free rotation) and every sphere's
  // own-frame coordinate, exactly. restore() expects the sizes of the saved state.
  void save(ByteWriter& w) const;
  void restore(ByteReader& r, int n_clusters, int n_spheres);

 private:
  void set_rotation(State<D>& s, int c, const Rotation<D>& space_from_principal, const Spin<D>& momentum, double t);
  void refresh_bounds(const State<D>& s, int c);

  std::vector<Body> body_;     // per cluster id
  std::vector<Vec<D>> coord_;  // per sphere: own-frame coordinate
};

// Kinetic energy of a state, translation plus rotation (eq. 2), with each cluster spinning
// at its angular velocity in s.spin (none if empty) and its inertia from its spheres.
template <int D>
double total_kinetic_energy(const State<D>& s);

// The mean kinetic energy per body (translation plus rotation): Richardson's reference for
// the collision outcomes (§3: "the initial mean kinetic energy"; §2.6).
template <int D>
double mean_kinetic_energy_per_body(const State<D>& s) {
  return total_kinetic_energy(s) / s.n_clusters();
}

extern template class RigidBodies<2>;
extern template class RigidBodies<3>;

}  // namespace ballagg
