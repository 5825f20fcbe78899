#pragma once
// Ordinary least squares y = intercept + slope x, with the standard errors of both
// parameters (the usual estimates from the residual variance, n - 2 degrees of freedom).
// Used for every power-law fit of the analysis: log N(eps) against log eps (4.7), log n(r)
// against log r (Richardson §3), log R_max and log rho against log N_a.
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace ballagg {

struct LinearFit {
  double slope = 0.0, intercept = 0.0;
  double slope_error = 0.0, intercept_error = 0.0;  // standard errors; 0 for an exact fit
  int points = 0;
};

// Needs at least 2 points with distinct x; with exactly 2 the errors are 0 (no residual
// to estimate them from) and are reported as NaN.
inline std::optional<LinearFit> fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  if (n < 2 || y.size() != n) return std::nullopt;
  double mx = 0.0, my = 0.0;
  for (std::size_t k = 0; k < n; ++k) mx += x[k], my += y[k];
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    sxx += (x[k] - mx) * (x[k] - mx);
    sxy += (x[k] - mx) * (y[k] - my);
  }
  if (!(sxx > 0.0)) return std::nullopt;
  LinearFit f;
  f.points = static_cast<int>(n);
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  if (n == 2) {
    f.slope_error = f.intercept_error = std::numeric_limits<double>::quiet_NaN();
    return f;
  }
  double rss = 0.0;
  double sx2 = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = y[k] - (f.intercept + f.slope * x[k]);
    rss += r * r;
    sx2 += x[k] * x[k];
  }
  const double variance = rss / static_cast<double>(n - 2);
  f.slope_error = std::sqrt(variance / sxx);
  f.intercept_error = std::sqrt(variance * sx2 / (static_cast<double>(n) * sxx));
  return f;
}

}  // namespace ballagg
