#include "ballagg/engines/time_stepping/retreat.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace ballagg {
namespace {

// The open interval of retreat fractions theta where |base - theta * drift| < reach (empty:
// lo >= hi), not clipped to [0, 1]: an interval containing 0 or 1 says so.
template <int D>
std::pair<double, double> too_close(const Vec<D>& base, const Vec<D>& drift, double reach) {
  constexpr std::pair<double, double> kNever{1.0, 0.0}, kAlways{-1.0, 2.0};
  const double a = drift.squaredNorm(), b = base.dot(drift), c = base.squaredNorm() - reach * reach;
  if (a == 0.0) return c < 0.0 ? kAlways : kNever;
  const double disc = b * b - a * c;
  if (disc <= 0.0) return kNever;
  const double root = std::sqrt(disc);
  return {(b - root) / a, (b + root) / a};
}

// The smallest theta >= 0 outside every open interval (above 1: none in [0, 1]).
double first_free(std::vector<std::pair<double, double>>& bad) {
  std::sort(bad.begin(), bad.end());
  double theta = 0.0;
  for (const auto& [lo, hi] : bad) {
    if (lo >= theta) break;  // sorted: no later interval starts before theta either
    if (hi > theta) theta = hi;
  }
  return theta;
}

}  // namespace

template <int D>
GroupSolution<D> place_at_contact(const ProblemContext<D>& ctx, const CollisionGroup& g) {
  const State<D>& s = ctx.state;
  const auto clusters = clusters_of_group(ctx, g);
  double longest_flight = 0.0, longest_shift = 0.0;
  for (const auto& [c, b] : clusters) {
    longest_flight = std::max(longest_flight, ctx.flight[c].norm());
    for (int i : s.clusters[c].members) longest_shift = std::max(longest_shift, ctx.step_shift[i].norm());
  }
  const double tolerance = retreat_tolerance(ctx.settings.daha);

  struct Candidate {
    SpherePair pair;
    Vec<D> base, drift;  // separation at theta: base - theta * drift
    double sigma;
  };
  std::vector<Candidate> candidates;
  std::vector<std::pair<double, double>> bad;  // retreat fractions where a pair is too close
  const double reach = 2.0 * (s.max_radius() + longest_flight + longest_shift);
  for_each_neighbour_of_group(ctx, g, reach, std::numeric_limits<int>::max(), [&](int i, int j, int bj) {
    const int ci = s.spheres.cluster[i], cj = s.spheres.cluster[j];
    const bool member = bj >= 0;
    const double sigma = s.spheres.radius[i] + s.spheres.radius[j];
    // The retreat starts where free flight put the group (this step's minimisations
    // undone); a sphere outside the group stays where it is now.
    const Vec<D> base = s.box.separation(ctx.positions[i] - ctx.step_shift[i],
                                         member ? Vec<D>(ctx.positions[j] - ctx.step_shift[j]) : ctx.positions[j]);
    const Vec<D> drift = member ? Vec<D>(ctx.flight[ci] - ctx.flight[cj]) : ctx.flight[ci];
    double too_near = sigma * (1.0 - tolerance);
    // A pair of the group that overlaps at theta = 1 (by up to eps_c, left by the last
    // step) is held to that, never made worse.
    if (member) too_near = std::min(too_near, (base - drift).norm());
    const auto interval = too_close<D>(base, drift, too_near);
    if (interval.first < interval.second && interval.second > 0.0) bad.push_back(interval);
    candidates.push_back({{std::min(i, j), std::max(i, j), 0.0}, base, drift, sigma});
  });
  const double theta = std::min(1.0, first_free(bad));

  GroupSolution<D> out;
  out.placed_at_contact = true;
  out.dissolves_bodies = true;
  out.result.converged = true;
  out.n_variables = static_cast<int>(clusters.size());
  const double eps_c = ctx.settings.daha.eps_c;
  for (const Candidate& k : candidates)
    if (std::abs((k.base - theta * k.drift).norm() / k.sigma - 1.0) <= eps_c) out.contacts.push_back(k.pair);
  for (const auto& [c, b] : clusters)
    for (int i : s.clusters[c].members) {
      const Vec<D> shift = -ctx.step_shift[i] - theta * ctx.flight[c];
      if (shift == Vec<D>::Zero()) continue;
      out.spheres.push_back(i);
      out.shift.push_back(shift);
    }
  return out;
}

template GroupSolution<2> place_at_contact<2>(const ProblemContext<2>&, const CollisionGroup&);
template GroupSolution<3> place_at_contact<3>(const ProblemContext<3>&, const CollisionGroup&);

}  // namespace ballagg
