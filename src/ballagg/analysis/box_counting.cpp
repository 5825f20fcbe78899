#include "ballagg/analysis/box_counting.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ballagg {
namespace {

// Levels that fit in a 64-bit Morton key: 31 in 2D, 21 in 3D.
template <int D>
constexpr int kMaxLevel = 63 / D;

template <int D>
std::uint64_t morton_key(const std::array<std::uint32_t, D>& c, int bits) {
  std::uint64_t key = 0;
  for (int b = bits - 1; b >= 0; --b)
    for (int a = D - 1; a >= 0; --a) key = (key << 1) | ((c[a] >> b) & 1u);
  return key;
}

}  // namespace

template <int D>
BoxCounting box_counting(const Box<D>& box, const std::vector<Vec<D>>& points, double length_unit,
                         double largest_eps) {
  BoxCounting out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.dimension = out.dimension_error = out.prefactor = out.prefactor_error = nan;
  const double l = box.length;
  int finest = 1;
  while (finest < kMaxLevel<D> && l / std::ldexp(1.0, finest + 1) >= kBoxCountingFinest * length_unit) ++finest;

  const std::uint32_t cells = std::uint32_t{1} << finest;
  std::vector<std::uint64_t> keys(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::array<std::uint32_t, D> c;
    for (int a = 0; a < D; ++a) {
      const double u = std::floor(points[i][a] / l * cells);
      c[a] = static_cast<std::uint32_t>(std::clamp(u, 0.0, static_cast<double>(cells - 1)));
    }
    keys[i] = morton_key<D>(c, finest);
  }
  std::sort(keys.begin(), keys.end());

  std::vector<double> log_eps, log_n;
  for (int m = 1; m <= finest; ++m) {
    const int drop = D * (finest - m);  // a level-m cell is the key without its last bits
    std::int64_t distinct = keys.empty() ? 0 : 1;
    for (std::size_t k = 1; k < keys.size(); ++k) distinct += (keys[k] >> drop) != (keys[k - 1] >> drop);
    const double eps = std::ldexp(l, -m);
    const bool in_range = eps >= kBoxCountingSmallest * length_unit && eps <= std::min(0.5 * l, largest_eps);
    out.level.push_back(m);
    out.eps.push_back(eps);
    out.boxes.push_back(distinct);
    out.fitted.push_back(in_range);
    if (in_range && distinct > 0) {
      log_eps.push_back(std::log(eps));
      log_n.push_back(std::log(static_cast<double>(distinct)));
    }
  }
  out.fit = fit_line(log_eps, log_n);
  // N(eps_m) <= 2^D N(eps_(m-1)) (a cell has 2^D children), so the slope never exceeds D:
  // the number of levels is the only thing to judge.
  out.flaw = out.fit && out.fit->points >= kMinFitPoints ? FitFlaw::none : FitFlaw::too_few_points;
  if (out.flaw == FitFlaw::none) {
    out.dimension = -out.fit->slope;
    out.dimension_error = out.fit->slope_error;
    out.prefactor = std::exp(out.fit->intercept);
    out.prefactor_error = out.prefactor * out.fit->intercept_error;
  }
  return out;
}

template BoxCounting box_counting<2>(const Box<2>&, const std::vector<Vec<2>>&, double, double);
template BoxCounting box_counting<3>(const Box<3>&, const std::vector<Vec<3>>&, double, double);

}  // namespace ballagg
