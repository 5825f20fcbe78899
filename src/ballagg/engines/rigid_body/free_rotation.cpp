#include "ballagg/engines/rigid_body/free_rotation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_3.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

namespace ballagg {
namespace {

// Plain double precision (Boost would otherwise evaluate in long double, twice as slow),
// and errors raised as exceptions (the arguments below are always in range).
using ElliptPolicy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;

// The modulus is kept this far below 1: on the separatrix itself (k = 1) the motion takes
// forever to reach the unstable axis and the periodic formulas break down; a body there
// by round-off moves as one a relative 4 ulp away from it.
constexpr double kMaxModulusSquared = 1.0 - 4.0 * std::numeric_limits<double>::epsilon();

// F(phi | k), the incomplete integral of the first kind, for phi in [-pi, pi].
double first_kind(double k, double phi, double complete) {
  constexpr double half_pi = std::numbers::pi / 2;
  const double a = std::abs(phi);
  const double f = a <= half_pi ? boost::math::ellint_1(k, a, ElliptPolicy())
                                : 2.0 * complete - boost::math::ellint_1(k, std::numbers::pi - a, ElliptPolicy());
  return phi < 0 ? -f : f;
}

// Rz(phi) Rx(theta) Rz(psi), with theta and psi given by the direction n of the body-frame
// angular momentum: n = (sin theta sin psi, sin theta cos psi, cos theta).
Rotation<3> euler_rotation(double phi, const Vec<3>& n) {
  const double st = std::hypot(n[0], n[1]), ct = n[2];
  const double sp = st > 0.0 ? n[0] / st : 0.0, cp = st > 0.0 ? n[1] / st : 1.0;
  const double sf = std::sin(phi), cf = std::cos(phi);
  Rotation<3> r;
  r << cf * cp - sf * ct * sp, -cf * sp - sf * ct * cp, sf * st,  //
      sf * cp + cf * ct * sp, -sf * sp + cf * ct * cp, -cf * st,  //
      st * sp, st * cp, ct;
  return r;
}

}  // namespace

FreeRotation<3>::FreeRotation(const Vec<3>& moments, const Eigen::Quaterniond& orientation, const Spin<3>& h,
                              double t0, const Rotation<3>& frame)
    : moments_(moments), r0_(orientation.normalized().toRotationMatrix()), h_(h), t0_(t0) {
  // Order the principal axes by moment; the ordering is a proper rotation S.
  std::array<int, 3> p{0, 1, 2};
  std::sort(p.begin(), p.end(), [&](int a, int b) { return moments[a] < moments[b] || (moments[a] == moments[b] && a < b); });
  Rotation<3> s = Rotation<3>::Zero();
  for (int a = 0; a < 3; ++a) s(a, p[a]) = 1.0;
  if (s.determinant() < 0) s.row(2) *= -1.0;
  Vec<3> sorted(moments[p[0]], moments[p[1]], moments[p[2]]);
  const double tie = kMomentTie * sorted[2];
  if (sorted[1] - sorted[0] <= tie) sorted[0] = sorted[1] = 0.5 * (sorted[0] + sorted[1]);
  if (sorted[2] - sorted[1] <= tie) sorted[1] = sorted[2] = 0.5 * (sorted[1] + sorted[2]);
  if (sorted[2] - sorted[0] <= tie) sorted[0] = sorted[1] = sorted[2] = sorted.mean();
  for (int a = 0; a < 3; ++a) moments_[p[a]] = sorted[a];

  const Vec<3> m = s * r0_.transpose() * h;  // body-frame angular momentum, ordered axes
  own0_ = r0_ * frame.transpose();
  energy_ = 0.5 * m.cwiseProduct(m).cwiseQuotient(sorted).sum();
  if (m.squaredNorm() == 0.0) return;  // at rest
  const double e3 = (m.cwiseProduct(m).cwiseProduct(Vec<3>::Constant(sorted[2]).cwiseQuotient(sorted) - Vec<3>::Ones())).sum();
  const double e1 = (m.cwiseProduct(m).cwiseProduct(Vec<3>::Ones() - Vec<3>::Constant(sorted[0]).cwiseQuotient(sorted))).sum();
  const double q = (sorted[1] - sorted[0]) * e3, r = (sorted[2] - sorted[1]) * e1;
  const int zeros = (m[0] == 0.0) + (m[1] == 0.0) + (m[2] == 0.0);
  if ((q == 0.0 && r == 0.0) || zeros >= 2) {
    // The angular velocity is parallel to h and constant: uniform rotation.
    kind_ = Kind::uniform;
    omega_ = r0_ * s.transpose() * m.cwiseQuotient(sorted);
    max_speed_ = omega_.norm();
    return;
  }
  kind_ = Kind::elliptic;
  const bool swap = q > r;  // the motion circles the axis of smallest moment
  const double k2 = std::min(swap ? r / q : q / r, kMaxModulusSquared);
  const double lambda2 = std::max(q, r) / (sorted[0] * sorted[1] * sorted[2]);
  // Ordered body frame: (cn, sn, dn) axes = (1, 2, 3), or (3, 2, -1) when swapped.
  Rotation<3> f = Rotation<3>::Identity();
  if (swap) f << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  j_ = swap ? Vec<3>(sorted[2], sorted[1], sorted[0]) : sorted;
  const Vec<3> mf = f * m;
  const double spread = sorted[2] - sorted[0];
  const double a_cn2 = (swap ? sorted[2] * e1 : sorted[0] * e3) / spread;
  const double a_dn2 = (swap ? sorted[0] * e3 : sorted[2] * e1) / spread;
  const double a_sn2 = a_cn2 + k2 * a_dn2;
  const double sign = mf[2] >= 0.0 ? 1.0 : -1.0;
  amplitude_ = Vec<3>(std::sqrt(a_cn2), std::sqrt(a_sn2), sign * std::sqrt(a_dn2));
  h_norm_ = m.norm();
  k_ = std::sqrt(k2);
  quarter_period_ = boost::math::ellint_1(k_, ElliptPolicy());
  // Euler's equations in the ordered frame fix the sign: m1' = m2 m3 (1/J3 - 1/J2).
  lambda_ = sign * (j_[1] < j_[2] ? 1.0 : -1.0) * std::sqrt(lambda2);
  u0_ = first_kind(k_, std::atan2(mf[1] / amplitude_[1], mf[0] / amplitude_[0]), quarter_period_);
  n_ = k2 * a_dn2 / a_cn2;
  half_period_integral_ = 2.0 * boost::math::ellint_3(k_, -n_, ElliptPolicy());
  precession_rate_ = h_norm_ / j_[2];
  precession_coefficient_ = h_norm_ * (1.0 / j_[0] - 1.0 / j_[2]) / lambda_;
  double sn, cn, dn;
  phase_integral_0_ = phase_integral(u0_, &sn, &cn, &dn);
  const Rotation<3> b0 = euler_rotation(0.0, amplitude_.cwiseProduct(Vec<3>(cn, sn, dn)).normalized());
  right_ = f * s;
  left_ = r0_ * right_.transpose() * b0.transpose();
  right_ = right_ * frame.transpose();
  // |omega|^2 = sum m_i^2 / J_i^2 is linear in sn^2 (cn^2 = 1 - sn^2, dn^2 = 1 - k^2 sn^2):
  // its largest value is at sn^2 = 0 or 1.
  const Vec<3> w2 = amplitude_.cwiseQuotient(j_).cwiseAbs2();
  max_speed_ = std::sqrt(std::max(w2[0] + w2[2], w2[1] + (1.0 - k2) * w2[2]));
  slow_nutation_ = std::abs(lambda_) < kSlowNutation * h_norm_ / j_.minCoeff();
  max_acceleration_ = h_norm_ * max_speed_ / j_.minCoeff();
}

double FreeRotation<3>::phase_integral(double u, double* sn, double* cn, double* dn) const {
  // Reduce u to r in [-K, K]: sn and cn change sign every 2K, the integrand has period 2K.
  const double period = 2.0 * quarter_period_;
  const double turns = std::nearbyint(u / period);
  const double rest = u - turns * period;
  *sn = boost::math::jacobi_elliptic(k_, rest, cn, dn, ElliptPolicy());
  const double amplitude = std::atan2(*sn, *cn);  // am(rest), in [-pi/2, pi/2]
  if (std::fmod(std::abs(turns), 2.0) == 1.0) {
    *sn = -*sn;
    *cn = -*cn;
  }
  return turns * half_period_integral_ + boost::math::ellint_3(k_, -n_, amplitude, ElliptPolicy());
}

double FreeRotation<3>::phase_increment(double du) const {
  // 8-point Gauss-Legendre on [u0, u0 + du] of 1 / (1 + N sn^2 u).
  static constexpr double node[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
  static constexpr double weight[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  double sum = 0.0;
  for (int k = 0; k < 4; ++k) {
    for (double side : {-1.0, 1.0}) {
      double cn, dn;
      const double sn = boost::math::jacobi_elliptic(k_, u0_ + 0.5 * du * (1.0 + side * node[k]), &cn, &dn, ElliptPolicy());
      sum += weight[k] / (1.0 + n_ * sn * sn);
    }
  }
  return 0.5 * du * sum;
}

FreeRotation<3>::Pose FreeRotation<3>::at(double t) const {
  switch (kind_) {
    case Kind::rest:
      return {own0_, Spin<3>::Zero()};
    case Kind::uniform: {
      const double speed = omega_.norm();
      return {Eigen::AngleAxisd(speed * (t - t0_), omega_ / speed).toRotationMatrix() * own0_, omega_};
    }
    case Kind::elliptic:
      break;
  }
  const double dt = t - t0_;
  const double du = lambda_ * dt;
  double sn, cn, dn;
  // The increment of the phase integral since t0. Written as a difference of two
  // elliptic integrals it loses the digits of u0 / du, which precession_coefficient_
  // (proportional to 1 / lambda) then magnifies: where the nutation is slow (lambda
  // small against the spin) and du short, it is integrated directly.
  double increment;
  if (n_ == 0.0) {  // symmetric top (k = 0): sn, cn = sin, cos and the integrand is 1
    if (k_ == 0.0) {
      sn = std::sin(u0_ + du);
      cn = std::cos(u0_ + du);
      dn = 1.0;
    } else {
      phase_integral(u0_ + du, &sn, &cn, &dn);
    }
    increment = du;
  } else if (slow_nutation_ && std::abs(du) <= 1.0) {
    phase_integral(u0_ + du, &sn, &cn, &dn);
    increment = phase_increment(du);
  } else {
    increment = phase_integral(u0_ + du, &sn, &cn, &dn) - phase_integral_0_;
  }
  const double phi = precession_rate_ * dt + precession_coefficient_ * increment;
  const Vec<3> mf = amplitude_.cwiseProduct(Vec<3>(cn, sn, dn));
  const Rotation<3> b = left_ * euler_rotation(phi, mf.normalized());
  return {b * right_, b * mf.cwiseQuotient(j_)};
}

}  // namespace ballagg
