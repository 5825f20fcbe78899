#pragma once
// Size, density and the mass-radius fractal dimension of one aggregate (Richardson 1995,
// §2.2 and §3):
//   R_max = max_i (r_i + R_i)                        (Richardson eq. 7)
// with r_i the distance of centre i from the aggregate's centre of mass; the spherically
// averaged density rho = M / (volume of a ball of radius R_max) (pi R_max^2 in 2D); and
// f_D, "the slope of a log-log plot of radius measured from the center of mass vs
// enclosed particle number": n(r) = #{i : r_i <= r} tabulated at radii growing by the
// factor kMassRadiusRatio, fitted by least squares on kMassRadiusInner R <= r <= R_g
// (beyond a couple of diameters, where n(r) is the count of single spheres, and inside
// the radius of gyration, before n(r) saturates at the aggregate's edge).
//
// Richardson's own estimate, as his §3 describes it and as his Figs. 6b, 8b and 10b plot
// it down to aggregates of a few spheres: the same slope fitted through every centre,
// log n(r_i) against log r_i for every centre with r_i >= R (R: the mean radius; a centre
// almost on the centre of mass would weigh in at log r -> -infinity), to the farthest.
// It needs no fit range, and still means something for the small and fluffy aggregates
// of his runs, whose centre of mass often lies in a hole several radii wide (the windowed
// fit then starts on the steep rise after the hole and gives 3 or more in 3D); it is
// pulled down by the saturation at the edge. Both are reported.
//
// A fit is withheld (NaN, with its FitFlaw, fit_flaw.hpp) when it cannot mean what it says:
// the windowed fit when no centre lies within kMassRadiusInner R of the centre of mass (its
// window then starts on the far edge of a hole), or when it has fewer than kMinFitPoints
// radii; either fit when its slope is outside (0, D + kDimensionExcess]. Richardson's fit
// is kept through a hole, which is what it is for; a hole wide enough to push it above D
// is caught by the range.
#include <optional>
#include <span>
#include <vector>

#include "ballagg/analysis/fit_flaw.hpp"
#include "ballagg/analysis/linear_fit.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

inline constexpr double kMassRadiusInner = 4.0;                // smallest fitted r, in units of R
inline constexpr double kMassRadiusRatio = 1.189207115002721;  // 2^(1/4): four radii per octave
inline constexpr int kRichardsonMinSize = 4;                   // fewer spheres: no Richardson f_D

template <int D>
struct MassRadius {
  Vec<D> centre_of_mass = Vec<D>::Zero();
  double mass = 0.0;
  double r_max = 0.0;     // (7)
  double density = 0.0;   // M / (volume of the ball of radius R_max)
  std::vector<double> radius;                // the table's radii r
  std::vector<std::int64_t> enclosed;        // n(r)
  std::vector<char> fitted;                  // r within the fitted range
  double nearest_centre = 0.0;               // distance of the nearest centre from the centre of mass
  std::optional<LinearFit> fit;              // log n against log r: slope = f_D (kept when withheld)
  double dimension = 0.0, dimension_error = 0.0;  // NaN when withheld
  FitFlaw dimension_flaw = FitFlaw::none;
  // Richardson's fit through every centre; NaN when withheld (below kRichardsonMinSize spheres).
  double richardson_dimension = 0.0, richardson_dimension_error = 0.0;
  FitFlaw richardson_flaw = FitFlaw::none;
};

// One aggregate: its centres (in one piece, see cluster_unwrapping.hpp), radii and masses
// indexed by `members`. length_unit: R (the mean radius); radius_of_gyration: R_g of the
// aggregate (gyration.hpp), the upper end of the fit.
template <int D>
MassRadius<D> mass_radius(std::span<const std::int32_t> members, const std::vector<Vec<D>>& position,
                          const std::vector<double>& radius, const std::vector<double>& mass, double length_unit,
                          double radius_of_gyration);

// The volume of a ball of radius r in D dimensions (pi r^2, 4/3 pi r^3).
template <int D>
double ball_volume(double r);

extern template MassRadius<2> mass_radius<2>(std::span<const std::int32_t>, const std::vector<Vec<2>>&,
                                             const std::vector<double>&, const std::vector<double>&, double, double);
extern template MassRadius<3> mass_radius<3>(std::span<const std::int32_t>, const std::vector<Vec<3>>&,
                                             const std::vector<double>&, const std::vector<double>&, double, double);

}  // namespace ballagg
