#pragma once
// Torque-free rotation of a rigid body: Euler's equations (Richardson 1995 eq. 5) with the
// principal axes moving as (6), solved exactly rather than integrated.
//
// Between collisions a body's spin angular momentum h (space frame) is constant, and so is
// its rotational energy. Richardson integrates the 12 components of (5)-(6) with a
// Runge-Kutta method; the axes then drift from orthonormality and the invariants drift
// with the step. Here the orientation at any time t is a closed-form function of the state
// at the last collision, t0 (Landau & Lifshitz, Mechanics §37; Celledoni, Fassò, Säfström
// & Zanna 2008):
//   * the body-frame angular momentum m(t) = (A_cn cn u, A_sn sn u, A_dn dn u) with Jacobi
//     elliptic functions of u = u0 + lambda (t - t0), in the principal frame ordered so
//     that the dn axis is the one m(t) never crosses (largest or smallest moment);
//   * the orientation as z-x-z Euler angles in the frame where h is along z: theta and
//     psi from m(t), and the precession angle phi from
//     phi' = M (m1^2/J1 + m2^2/J2) / (m1^2 + m2^2) = M/J3 + M (1/J1 - 1/J3) / (1 + N sn^2 u),
//     whose integral is an incomplete elliptic integral of the third kind.
// Nothing accumulates: evaluating at any t costs the same and the invariants hold to
// round-off however long the body flies (test: 10^4 rotation periods). Jacobi functions
// and elliptic integrals come from Boost.Math.
//
// 2D: the spin is a scalar and constant between collisions; the orientation is an angle
// growing linearly.
#include <cmath>
#include <cstdint>
#include <type_traits>

#include <Eigen/Geometry>

#include "ballagg/core/spin.hpp"

namespace ballagg {

template <int D>
class FreeRotation;

// Principal moments that agree to this relative difference are made equal: a body with
// two equal moments (a dimer, any body with an axis of symmetry of order >= 3) then
// precesses regularly instead of through elliptic functions of a modulus near 0 or 1
// whose ratio is round-off. Changes the moments by at most this fraction.
inline constexpr double kMomentTie = 1e-12;
// Nutation slower than this fraction of the spin (|lambda| < kSlowNutation M / J_min: nearly
// symmetric bodies spinning nearly about a principal axis or in the plane of two almost
// equal moments) has its precession integral evaluated by quadrature over short spans.
inline constexpr double kSlowNutation = 1e-6;

template <>
class FreeRotation<3> {
 public:
  // Where a body is at time t: its orientation (space <- the frame given at construction)
  // and its angular velocity in the space frame.
  struct Pose {
    Rotation<3> rotation;
    Spin<3> angular_velocity;
  };

  FreeRotation() = default;  // at rest, principal frame = space frame
  // moments: principal moments I_1, I_2, I_3 > 0 (any order); orientation: space <-
  // principal frame at time t0; h: spin angular momentum about the centre of mass (space);
  // frame: the principal axes in the frame whose orientation at() returns (that frame <-
  // principal frame; the principal frame itself by default).
  FreeRotation(const Vec<3>& moments, const Eigen::Quaterniond& orientation, const Spin<3>& h, double t0,
               const Rotation<3>& frame = Rotation<3>::Identity());

  Pose at(double t) const;
  Rotation<3> rotation_at(double t) const { return at(t).rotation; }

  const Spin<3>& angular_momentum() const { return h_; }
  const Vec<3>& moments() const { return moments_; }
  double reference_time() const { return t0_; }
  // Rotational kinetic energy 1/2 omega . h (eq. 2), constant in free flight.
  double energy() const { return energy_; }
  // Bounds on |omega(t)| and |d omega / dt| over the whole free flight.
  double max_angular_speed() const { return max_speed_; }
  double max_angular_acceleration() const { return max_acceleration_; }
  bool rotating() const { return kind_ != Kind::rest; }

  // Checkpoints (core/byte_stream.hpp writer and reader): every member as it is, so that a
  // restored rotation gives the saved one's poses bit for bit (building it again from the
  // orientation at t0 would, but the orientation passed through a quaternion is not kept).
  template <class Writer>
  void save(Writer& w) const {
    fields(*this, [&](const auto& x) { w.put(x); });
  }
  template <class Reader>
  void restore(Reader& r) {
    fields(*this, [&](auto& x) { x = r.template get<std::remove_cvref_t<decltype(x)>>("free rotation"); });
    if (kind_ != Kind::rest && kind_ != Kind::uniform && kind_ != Kind::elliptic) r.fail("unknown kind of free rotation");
  }

 private:
  enum class Kind : std::uint8_t { rest, uniform, elliptic };

  template <class Self, class F>
  static void fields(Self& self, F&& f) {
    f(self.kind_), f(self.moments_), f(self.r0_), f(self.own0_), f(self.h_), f(self.t0_), f(self.energy_);
    f(self.max_speed_), f(self.max_acceleration_), f(self.omega_), f(self.left_), f(self.right_), f(self.j_);
    f(self.amplitude_), f(self.h_norm_), f(self.k_), f(self.quarter_period_), f(self.lambda_), f(self.u0_);
    f(self.n_), f(self.half_period_integral_), f(self.phase_integral_0_), f(self.precession_rate_);
    f(self.precession_coefficient_), f(self.slow_nutation_);
  }

  void set_up_elliptic(const Vec<3>& sorted_moments, const Vec<3>& m);

  Kind kind_ = Kind::rest;
  Vec<3> moments_ = Vec<3>::Ones();
  Rotation<3> r0_ = Rotation<3>::Identity();    // orientation at t0 (space <- principal)
  Rotation<3> own0_ = Rotation<3>::Identity();  // the same, of the output frame
  Spin<3> h_ = Spin<3>::Zero();
  double t0_ = 0.0;
  double energy_ = 0.0;
  double max_speed_ = 0.0;
  double max_acceleration_ = 0.0;
  // Uniform rotation about a fixed axis (spherical body, or h along a principal axis or in
  // the plane of two equal moments).
  Spin<3> omega_ = Spin<3>::Zero();
  // Elliptic motion: orientation(t) = left_ * Rz(phi) Rx(theta) Rz(psi) * right_.
  Rotation<3> left_ = Rotation<3>::Identity();   // h-frame -> space
  Rotation<3> right_ = Rotation<3>::Identity();  // output frame -> ordered body frame
  Vec<3> j_ = Vec<3>::Ones();                    // moments in the ordered body frame
  Vec<3> amplitude_ = Vec<3>::Zero();            // A_cn, A_sn, s A_dn
  double h_norm_ = 0.0;                          // M = |h|
  double k_ = 0.0, quarter_period_ = 0.0;        // modulus and K(k)
  double lambda_ = 0.0, u0_ = 0.0;               // u = u0 + lambda (t - t0)
  double n_ = 0.0;                               // N of the precession integral
  double half_period_integral_ = 0.0;            // integral of du / (1 + N sn^2 u) over 2K
  double phase_integral_0_ = 0.0;                // its indefinite value at u0
  double precession_rate_ = 0.0;                 // M / J3
  double precession_coefficient_ = 0.0;          // M (1/J1 - 1/J3) / lambda
  std::uint8_t slow_nutation_ = 0;  // bool, as a byte for checkpoints

  // The integral of du / (1 + N sn^2 u) from 0 to u, and the elliptic functions at u.
  double phase_integral(double u, double* sn, double* cn, double* dn) const;
  // The same integral from u0 to u0 + du, by quadrature (short du only).
  double phase_increment(double du) const;
};

template <>
class FreeRotation<2> {
 public:
  struct Pose {
    Rotation<2> rotation;
    Spin<2> angular_velocity;
  };

  FreeRotation() = default;
  // moment: the moment of inertia about the normal; angle: the body's orientation at t0;
  // h: its spin angular momentum.
  FreeRotation(double moment, double angle, const Spin<2>& h, double t0)
      : moment_(moment), angle0_(angle), h_(h), t0_(t0), omega_(h[0] / moment) {}

  Pose at(double t) const { return {plane_rotation(angle_at(t)), Spin<2>(omega_)}; }
  Rotation<2> rotation_at(double t) const { return plane_rotation(angle_at(t)); }
  double angle_at(double t) const { return angle0_ + omega_ * (t - t0_); }

  const Spin<2>& angular_momentum() const { return h_; }
  Spin<2> moments() const { return Spin<2>(moment_); }
  double reference_time() const { return t0_; }
  double energy() const { return 0.5 * h_[0] * omega_; }
  double max_angular_speed() const { return std::abs(omega_); }
  double max_angular_acceleration() const { return 0.0; }
  bool rotating() const { return omega_ != 0.0; }

  template <class Writer>
  void save(Writer& w) const {
    w.put(moment_), w.put(angle0_), w.put(h_), w.put(t0_), w.put(omega_);
  }
  template <class Reader>
  void restore(Reader& r) {
    moment_ = r.template get<double>("moment"), angle0_ = r.template get<double>("angle");
    h_ = r.template get<Spin<2>>("spin"), t0_ = r.template get<double>("time"), omega_ = r.template get<double>("spin");
  }

 private:
  double moment_ = 1.0;
  double angle0_ = 0.0;
  Spin<2> h_ = Spin<2>::Zero();
  double t0_ = 0.0;
  double omega_ = 0.0;
};

}  // namespace ballagg
