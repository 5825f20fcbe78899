#include "ballagg/analysis/mass_radius.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ballagg {

template <int D>
double ball_volume(double r) {
  if constexpr (D == 2) return std::numbers::pi * r * r;
  else return 4.0 / 3.0 * std::numbers::pi * r * r * r;
}

namespace {

// Richardson's estimate: log n(r_i) against log r_i through every centre (r sorted) at
// least one radius from the centre of mass (a centre almost on it would weigh in at
// log r -> -infinity).
template <int D>
void richardson_fit(const std::vector<double>& r, double length_unit, MassRadius<D>& out) {
  if (static_cast<int>(r.size()) < kRichardsonMinSize) {
    out.richardson_flaw = FitFlaw::cluster_too_small;
    return;
  }
  std::vector<double> log_r, log_n;
  for (auto k = r.begin(); k != r.end(); ++k) {
    if (*k < length_unit) continue;
    const auto n = std::upper_bound(k, r.end(), *k) - r.begin();  // ties: all of them
    log_r.push_back(std::log(*k));
    log_n.push_back(std::log(static_cast<double>(n)));
  }
  const std::optional<LinearFit> f = fit_line(log_r, log_n);
  if (!f || f->points < kMinFitPoints) {
    out.richardson_flaw = FitFlaw::too_few_points;
    return;
  }
  out.richardson_flaw = dimension_range_flaw<D>(f->slope);
  if (out.richardson_flaw != FitFlaw::none) return;
  out.richardson_dimension = f->slope;
  out.richardson_dimension_error = f->slope_error;
}

// The windowed fit's flaw: a hole at the centre first (its slope is then meaningless
// whatever its value), then the number of radii, then the range.
template <int D>
FitFlaw windowed_flaw(const MassRadius<D>& m, double inner) {
  if (m.nearest_centre > inner) return FitFlaw::hole_at_centre;
  if (!m.fit || m.fit->points < kMinFitPoints) return FitFlaw::too_few_points;
  return dimension_range_flaw<D>(m.fit->slope);
}

}  // namespace

template <int D>
MassRadius<D> mass_radius(std::span<const std::int32_t> members, const std::vector<Vec<D>>& x,
                          const std::vector<double>& radius, const std::vector<double>& mass, double length_unit,
                          double radius_of_gyration) {
  MassRadius<D> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.dimension = out.dimension_error = out.richardson_dimension = out.richardson_dimension_error = nan;
  for (int i : members) {
    out.centre_of_mass += mass[i] * x[i];
    out.mass += mass[i];
  }
  out.centre_of_mass /= out.mass;
  std::vector<double> r;
  r.reserve(members.size());
  for (int i : members) {
    const double ri = (x[i] - out.centre_of_mass).norm();
    r.push_back(ri);
    out.r_max = std::max(out.r_max, ri + radius[i]);
  }
  out.density = out.mass / ball_volume<D>(out.r_max);
  std::sort(r.begin(), r.end());
  out.nearest_centre = r.empty() ? 0.0 : r.front();

  // The table: from the first radius of the fitted range (or the aggregate's edge if that
  // is closer) down by whole ratios to below one radius, and up to R_max.
  const double inner = kMassRadiusInner * length_unit;
  double start = inner;
  while (start > length_unit) start /= kMassRadiusRatio;
  std::vector<double> log_r, log_n;
  for (double rk = start; rk <= out.r_max * kMassRadiusRatio; rk *= kMassRadiusRatio) {
    const auto n = static_cast<std::int64_t>(std::upper_bound(r.begin(), r.end(), rk) - r.begin());
    // Round-off in the repeated products must not drop the range's own end points.
    const bool in_range = rk >= inner * (1.0 - 1e-12) && rk <= radius_of_gyration && n > 0;
    out.radius.push_back(rk);
    out.enclosed.push_back(n);
    out.fitted.push_back(in_range);
    if (in_range) {
      log_r.push_back(std::log(rk));
      log_n.push_back(std::log(static_cast<double>(n)));
    }
  }
  richardson_fit(r, length_unit, out);
  out.fit = fit_line(log_r, log_n);
  out.dimension_flaw = windowed_flaw(out, inner);
  if (out.dimension_flaw == FitFlaw::none) {
    out.dimension = out.fit->slope;
    out.dimension_error = out.fit->slope_error;
  }
  return out;
}

template double ball_volume<2>(double);
template double ball_volume<3>(double);
template MassRadius<2> mass_radius<2>(std::span<const std::int32_t>, const std::vector<Vec<2>>&,
                                      const std::vector<double>&, const std::vector<double>&, double, double);
template MassRadius<3> mass_radius<3>(std::span<const std::int32_t>, const std::vector<Vec<3>>&,
                                      const std::vector<double>&, const std::vector<double>&, double, double);

}  // namespace ballagg
