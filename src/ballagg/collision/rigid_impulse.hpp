#pragma once
// Point-contact collisions of rotating rigid bodies: restitution with the generalised
// coefficients of Brach (1994) as set out by Richardson (1995) §2.5, eqs. (13)-(28).
//
// At the contact point, n is the unit normal from body 1 to body 2 and u the velocity of
// body 2's contact point relative to body 1's, u = v2 + w2 x c2 - v1 - w1 x c1 (c_i: the
// contact point relative to body i's centre of mass). An impulse P on body 1 (and -P on
// body 2) changes the velocities by (13)-(14), i.e. (18)-(19):
//   m1 dv1 = P,  I1 dw1 = c1 x P,  m2 dv2 = -P,  I2 dw2 = -c2 x P,
// and u by -K P with the collision matrix
//   K P = P/m1 + P/m2 + (I1^-1 (c1 x P)) x c1 + (I2^-1 (c2 x P)) x c2.
// The coefficients fix P: u'_n = -eps_n u_n (15), P_t = mu_t P_n (16), P_p = mu_p P_n (17).
// So P = P_n d with d = n + mu_t t + mu_p p, and (15) gives
//   P_n = (1 + eps_n) u_n / (n . K d).
// For mu_t = mu_p = 0 this is Richardson's closed form (23)-(28): n . K n = 1/(gamma mu) with
// gamma of (24) (the quadratic forms of the inverse inertia tensors in the ntp basis are
// (c_i x n) . I_i^-1 (c_i x n)). With tangential coefficients the same formula is the
// solution of the full linear system (20)-(22), written in vector form.
//
// The tangential basis (Appendix: "t and p by Gram-Schmidt") is chosen so that the
// coefficients mean something physical: t is the direction in which body 1's contact
// point slides over body 2's, so mu_t > 0 is friction opposing the slip; p = n x t. When
// there is no slip (below kNoSlip of |u|) no direction is preferred and no tangential
// impulse acts. Whether given coefficients create energy depends on the geometry of each
// collision (Brach 1994): the change of kinetic energy dE = -P.u + P.K P / 2 is returned
// and the engine refuses a collision that would create energy.
//
// Shared by every body kind: a wall is a body of infinite mass (inverse mass and inverse
// inertia zero).
#include <cmath>

#include "ballagg/core/spin.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

// Slip speeds below this fraction of |u| count as no slip (no tangential direction).
inline constexpr double kNoSlip = 1e-12;

// A body at the instant of a collision, as the impulse law needs it.
template <int D>
struct ImpactBody {
  double inverse_mass = 0.0;
  InertiaTensor<D> inverse_inertia = InertiaTensor<D>::Zero();  // space frame, about the centre of mass
  Vec<D> velocity = Vec<D>::Zero();                             // of the centre of mass
  Spin<D> angular_velocity = Spin<D>::Zero();
  Vec<D> lever = Vec<D>::Zero();                                // contact point - centre of mass

  Vec<D> contact_velocity() const { return velocity + cross(angular_velocity, lever); }
  // Velocity change of the contact point per impulse P on this body.
  Vec<D> response(const Vec<D>& p) const {
    return inverse_mass * p + cross(Spin<D>(inverse_inertia * cross(lever, p)), lever);
  }
};

struct ImpactCoefficients {
  double normal_restitution = 1.0;  // eps_n in [0, 1] (15)
  double mu_t = 0.0;                // (16), along the slip
  double mu_p = 0.0;                // (17), across it (3D only)
};

template <int D>
struct Impact {
  bool approaching = false;      // u_n < 0: otherwise no impulse
  Vec<D> impulse = Vec<D>::Zero();  // P, on body 1 (body 2 receives -P)
  double normal_velocity = 0.0;  // u_n before
  double denominator = 0.0;      // n . K d: must be > 0
  double energy_change = 0.0;    // kinetic energy after - before
};

// The impulse of a collision with normal n (unit, from body 1 to body 2).
template <int D>
Impact<D> collision_impulse(const ImpactBody<D>& b1, const ImpactBody<D>& b2, const Vec<D>& n,
                            const ImpactCoefficients& k) {
  Impact<D> out;
  const Vec<D> u = b2.contact_velocity() - b1.contact_velocity();
  out.normal_velocity = u.dot(n);
  if (out.normal_velocity >= 0.0) return out;
  out.approaching = true;
  Vec<D> d = n;
  const Vec<D> slip = -(u - out.normal_velocity * n);  // of body 1's contact point over body 2's
  if ((k.mu_t != 0.0 || k.mu_p != 0.0) && slip.norm() > kNoSlip * u.norm()) {
    const Vec<D> t = slip.normalized();
    d += k.mu_t * t;
    if constexpr (D == 3) d += k.mu_p * n.cross(t);
  }
  auto collision_matrix = [&](const Vec<D>& p) -> Vec<D> { return b1.response(p) + b2.response(p); };
  out.denominator = n.dot(collision_matrix(d));
  if (!(out.denominator > 0.0)) return out;
  const double pn = (1.0 + k.normal_restitution) * out.normal_velocity / out.denominator;
  out.impulse = pn * d;
  out.energy_change = -out.impulse.dot(u) + 0.5 * out.impulse.dot(collision_matrix(out.impulse));
  return out;
}

// The normal coefficient of restitution of ice (Bridges, Hatzes & Lin 1984, Nature 309,
// 333), as Richardson's §3 uses it: eps_n = (v / v_c)^(-0.234) above v_c = 0.0077 cm/s,
// 1 below, with v the normal impact speed in cm/s.
inline constexpr double kBridgesCriticalSpeed = 0.0077;  // cm/s
inline constexpr double kBridgesExponent = -0.234;
inline double bridges_restitution(double normal_speed_cm_per_s) {
  if (normal_speed_cm_per_s <= kBridgesCriticalSpeed) return 1.0;
  return std::pow(normal_speed_cm_per_s / kBridgesCriticalSpeed, kBridgesExponent);
}

}  // namespace ballagg
