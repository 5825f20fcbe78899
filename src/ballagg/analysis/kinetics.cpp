#include "ballagg/analysis/kinetics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ballagg {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The automatic window: from the first time n <= kKineticsStartFraction n(0) to the last
// time n >= kKineticsEndClusters; empty (start > end) when the run never gets there.
std::pair<double, double> automatic_window(const KineticSeries& s) {
  double start = std::numeric_limits<double>::infinity(), end = -start;
  if (s.time.empty()) return {start, end};
  const double opening = kKineticsStartFraction * s.clusters.front();
  for (std::size_t k = 0; k < s.time.size(); ++k) {
    if (s.clusters[k] <= opening && s.time[k] < start) start = s.time[k];
    if (s.clusters[k] >= kKineticsEndClusters) end = s.time[k];
  }
  return {start, end};
}

// The rows nearest kKineticsSamples log-spaced times of [t0, t1] (t0 > 0), each once.
std::vector<std::size_t> log_spaced_rows(const std::vector<double>& time, double t0, double t1) {
  std::vector<std::size_t> rows;
  const auto first = std::lower_bound(time.begin(), time.end(), t0);
  const auto last = std::upper_bound(time.begin(), time.end(), t1);
  if (first >= last) return rows;
  for (int k = 0; k < kKineticsSamples; ++k) {
    const double target = t0 * std::pow(t1 / t0, k / (kKineticsSamples - 1.0));
    auto at = std::lower_bound(first, last, target);
    if (at == last || (at != first && target - *(at - 1) < *at - target)) --at;
    rows.push_back(static_cast<std::size_t>(at - time.begin()));
  }
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

DecayFit fit_decay(const KineticSeries& s, const std::vector<double>& y, const std::vector<std::size_t>& rows) {
  std::vector<double> lx, ly;
  for (std::size_t r : rows) {
    if (s.time[r] > 0.0 && y[r] > 0.0) {
      lx.push_back(std::log(s.time[r]));
      ly.push_back(std::log(y[r]));
    }
  }
  DecayFit d;
  d.fit = static_cast<int>(lx.size()) >= kMinFitPoints ? fit_line(lx, ly) : std::nullopt;
  if (!d.fit) {
    d.exponent = d.error = kNaN;
    d.flaw = FitFlaw::too_few_points;
    return d;
  }
  d.exponent = -d.fit->slope;
  d.error = d.fit->slope_error;
  return d;
}

}  // namespace

Kinetics fit_kinetics(const KineticSeries& s, std::optional<std::pair<double, double>> window) {
  Kinetics k;
  k.automatic_window = !window;
  const auto [t0, t1] = window ? *window : automatic_window(s);
  k.window_start = t0;
  k.window_end = t1;
  const std::vector<std::size_t> rows =
      t0 > 0.0 && t1 > t0 && std::isfinite(t1) ? log_spaced_rows(s.time, t0, t1) : std::vector<std::size_t>{};
  k.clusters = fit_decay(s, s.clusters, rows);
  k.energy = fit_decay(s, s.energy, rows);
  return k;
}

std::vector<CollapsePoint> scaling_collapse(double time, const std::vector<MassSpectrumBin>& spectrum) {
  double spheres = 0.0, clusters = 0.0;
  for (const MassSpectrumBin& b : spectrum) {
    spheres += static_cast<double>(b.size) * static_cast<double>(b.clusters);
    clusters += static_cast<double>(b.clusters);
  }
  std::vector<CollapsePoint> points;
  if (!(clusters > 0.0)) return points;
  const double mean = spheres / clusters;
  for (const MassSpectrumBin& b : spectrum) {
    if (!points.empty() && points.back().size == b.size) {  // bins of one size, other masses
      points.back().clusters += b.clusters;
      points.back().scaled_count = mean * mean * static_cast<double>(points.back().clusters) / spheres;
      continue;
    }
    points.push_back({time, b.size, b.clusters, mean, b.size / mean, mean * mean * static_cast<double>(b.clusters) / spheres});
  }
  return points;
}

}  // namespace ballagg
