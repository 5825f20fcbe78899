#include "ballagg/engines/time_stepping/retreat.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "ballagg/core/parallel.hpp"

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

// A pair is kept as a possible contact if its distance along the retreat comes within
// (1 + kCandidateReach eps_c) of its contact distance: a contact is a pair within eps_c of
// it at the end, and the margin of one more eps_c leaves the round-off no say.
constexpr double kCandidateReach = 2.0;

// The retreating spheres' paths are searched in pieces, checking after each whether any
// instant is still free: first kFirstRetreatPiece spheres (kParallelLoopMin when the group
// is large enough to share them among the threads), then a piece of 1 / kRetreatPieceGrowth
// of those already searched, so that at most about that fraction is searched beyond the
// point where the answer was known, for O(log) checks.
constexpr std::int64_t kFirstRetreatPiece = 8;
constexpr std::int64_t kRetreatPieceGrowth = 4;

template <int D>
Retreat<D> retreat_group(const StepView<D>& ctx, const CollisionGroup& g, bool with_candidates) {
  const State<D>& s = ctx.state;
  const QueriedClusters<D> queried(ctx, g, std::numeric_limits<int>::max());
  const auto& clusters = queried.clusters;  // (cluster, body index) of the group
  const double tolerance = retreat_tolerance(ctx.settings.daha);
  const double eps_c = ctx.settings.daha.eps_c;

  struct Candidate {
    SpherePair pair;
    Vec<D> base, drift;  // separation at theta: base - theta * drift
    double sigma;
  };
  // Per thread: the pairs looked at, and the retreat fractions where a pair is too close.
  // Their order does not matter: the intervals are sorted and the contacts put in pair
  // order below, so the result does not depend on the number of threads.
  struct Found {
    std::vector<Candidate> candidates;
    std::vector<std::pair<double, double>> bad;
    bool with_intervals = true;  // false once the verdict is known: only the contacts are wanted
  };
  std::vector<Found> found(max_threads());
  // Beyond the largest reach below (that of the largest contact distance) a pair is dropped
  // before its radii are read, with the same outcome.
  const double beyond_every_reach2 = beyond_squared(2.0 * s.max_radius() * (1.0 + kCandidateReach * eps_c));
  auto consider = [&](Found& out, int i, int j, int bj) {
    const int ci = s.spheres.cluster[i], cj = s.spheres.cluster[j];
    const bool member = bj >= 0;
    // The retreat starts where free flight put the group (this step's minimisations
    // undone); a sphere outside the group stays where it is now.
    const Vec<D> base = s.box.separation(ctx.positions[i] - ctx.step_shift[i],
                                         member ? Vec<D>(ctx.positions[j] - ctx.step_shift[j]) : ctx.positions[j]);
    const Vec<D> drift = member ? Vec<D>(ctx.flight[ci] - ctx.flight[cj]) : ctx.flight[ci];
    // Kept only if it can touch (within eps_c) at some theta in [0, 1]; the searches look
    // wider, and keeping every pair they meet took 288 MB in one retreat at N = 10^5 (3D).
    // A pair that stays farther apart than that all along the segment (most of the pairs
    // the searches meet) is not too close at any theta in [0, 1] either (too_near < reach):
    // its interval, if any, lies beyond theta = 1 and changes neither the theta that
    // first_free finds in [0, 1] nor whether there is one. So it is dropped at once.
    const double closest2 = squared_distance_to_segment<D>(Vec<D>::Zero(), base, -drift);
    if (closest2 > beyond_every_reach2) return;
    const double sigma = s.spheres.radius[i] + s.spheres.radius[j];
    const double reach = sigma * (1.0 + kCandidateReach * eps_c);
    if (closest2 > reach * reach) return;
    if (out.with_intervals) {
      double too_near = sigma * (1.0 - tolerance);
      // A pair of the group that overlaps at theta = 1 (by up to eps_c, left by the last
      // step) is held to that, never made worse.
      if (member) too_near = std::min(too_near, (base - drift).norm());
      const auto interval = too_close<D>(base, drift, too_near);
      if (interval.first < interval.second && interval.second > 0.0) out.bad.push_back(interval);
    }
    out.candidates.push_back({{std::min(i, j), std::max(i, j), 0.0}, base, drift, sigma});
  };
  // Only the pairs that the retreat can bring within contact distance are looked at. A
  // sphere i moves back along its cluster's flight, a segment: a sphere outside the group
  // (which stays where it is) matters only within a contact distance of that segment,
  // and a sphere of another cluster o of the group only within one of the segment of i's
  // motion relative to o. So: a narrow search around each such segment (wide enough for
  // the pairs left touching, eps_c, and for the cell list's slack), and o's spheres
  // listed directly when o is small, none at all when o's bounding sphere stays away.
  const GroupMarks marks(s.spheres.cluster, s.clusters.size(), queried.clusters);
  const double contact_reach = 2.0 * s.max_radius() * (1.0 + ctx.settings.daha.eps_c);
  const std::vector<RetreatStart<D>> starts = retreat_starts(ctx, clusters);
  // The clusters of the group that cluster k can meet: their bounding spheres come within
  // a contact distance along the relative flight. Tested per cluster pair first, since a
  // large group is a chain of clusters most of which are far from each other.
  auto can_meet = [&](std::size_t k, std::size_t m) {
    const Vec<D> relative_flight = ctx.flight[clusters[k].first] - ctx.flight[clusters[m].first];
    const Vec<D> between = s.box.separation(starts[k].centre, starts[m].centre);
    return distance_to_segment<D>(between, -relative_flight) <= starts[k].radius + starts[m].radius + contact_reach;
  };
  // Where each member of the group's small clusters starts its retreat, in member order: a
  // retreating sphere tries every member of a small partner (80 million tries in a run of
  // 10^6), each reading the scattered per-sphere arrays; read from here, a member that
  // cannot come near is passed over at the cost of consider()'s first test.
  std::vector<std::size_t> listed_first(clusters.size() + 1, 0);
  std::vector<Vec<D>> listed_start;
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    const Cluster<D>& cluster = s.clusters[clusters[k].first];
    if (cluster.size() <= kListedClusterSize)
      for (int j : cluster.members) listed_start.push_back(ctx.positions[j] - ctx.step_shift[j]);
    listed_first[k + 1] = listed_start.size();
  }
  std::vector<std::vector<std::size_t>> partners(clusters.size());
  std::vector<char> outside_searched(clusters.size());
  for (std::size_t k = 0; k < clusters.size(); ++k) outside_searched[k] = searched_against_outside(s, clusters[k].first);
  std::vector<std::pair<std::int32_t, std::int32_t>> retreating;  // (sphere, k) of the queried clusters
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    const int c = clusters[k].first;
    if (!queried(c)) continue;
    for (std::size_t m = 0; m < clusters.size(); ++m)
      if (m != k && can_meet(k, m)) partners[k].push_back(m);
    for (int i : s.clusters[c].members) retreating.push_back({i, static_cast<std::int32_t>(k)});
  }
  // The pairs of one retreating sphere i of the group's k-th cluster along the part of its
  // path from the retreat fraction `from` to 1 (0: the whole path; 1: its starting point,
  // the start of the step). With from = 0 every offset below is exactly the whole path's.
  auto look_around = [&](Found& out, int i, std::size_t k, double from) {
    const int c = clusters[k].first;
    const double span = 1.0 - from;
    const Vec<D> start = ctx.positions[i] - ctx.step_shift[i];
    for (std::size_t m : partners[k]) {
      // Not a structured binding: clang 14 cannot capture one in a lambda.
      const int other = clusters[m].first, other_body = clusters[m].second;
      const Vec<D> relative_flight = ctx.flight[c] - ctx.flight[other];
      const Vec<D> to_centre = s.box.separation(start, starts[m].centre);
      if (distance_to_segment<D>(Vec<D>(to_centre - from * relative_flight), Vec<D>(-(span * relative_flight))) >
          starts[m].radius + contact_reach)
        continue;
      const bool other_queried = queried(other);  // then a pair is taken from its lower sphere id's side
      auto member = [&](int j) {
        if (!(other_queried && j < i)) consider(out, i, j, other_body);
      };
      if (s.clusters[other].size() <= kListedClusterSize) {
        const std::vector<int>& members = s.clusters[other].members;
        const Vec<D>* member_start = listed_start.data() + listed_first[m];
        for (std::size_t q = 0; q < members.size(); ++q) {
          // consider()'s first test, to the bit: the same separation and drift.
          const Vec<D> base = s.box.separation(start, member_start[q]);
          if (squared_distance_to_segment<D>(Vec<D>::Zero(), base, -relative_flight) > beyond_every_reach2) continue;
          member(members[q]);
        }
        continue;
      }
      // The spheres of o are where the step's minimisations moved them, up to its
      // longest_shift from their start.
      auto in_other = [&](int j) {
        if (s.spheres.cluster[j] == other) member(j);
      };
      ctx.cells.for_each_near_segment(Vec<D>(start - from * relative_flight), Vec<D>(-(span * relative_flight)),
                                      contact_reach + starts[m].longest_shift + ctx.cell_slack, in_other);
    }
    if (!outside_searched[k]) return;
    auto outside = [&](int j) {
      if (s.spheres.cluster[j] != c && marks.body_index(j) < 0) consider(out, i, j, -1);
    };
    ctx.cells.for_each_near_segment(Vec<D>(start - from * ctx.flight[c]), Vec<D>(-(span * ctx.flight[c])),
                                    contact_reach + ctx.cell_slack, outside);
  };
  // Late in a large run a retreating group holds thousands of spheres: their searches are
  // shared among the threads.
  const std::int64_t n_retreating = static_cast<std::int64_t>(retreating.size());
  const bool parallel = n_retreating >= kParallelLoopMin;
  auto search = [&](std::int64_t begin, std::int64_t end, double from) {
#pragma omp parallel for schedule(dynamic, 64) if (parallel)
    for (std::int64_t r = begin; r < end; ++r)
      look_around(found[thread_index()], retreating[r].first, static_cast<std::size_t>(retreating[r].second), from);
  };
  // The paths are searched in pieces. When the intervals found so far leave no theta in
  // [0, 1] free, no later piece can free one (an interval only takes instants away): the
  // group goes back to the start of the step whatever the rest of its paths hold, and
  // only the pairs touching there are still wanted, found around each sphere's starting
  // point instead of along its path. Same result as searching every path, for less.
  std::vector<std::pair<double, double>> bad;
  auto gather_bad = [&] {
    for (Found& f : found) {
      bad.insert(bad.end(), f.bad.begin(), f.bad.end());
      f.bad.clear();
    }
  };
  std::int64_t searched = 0;
  bool blocked = false;  // no theta in [0, 1] free, found before every path was searched
  while (searched < n_retreating && !blocked) {
    const std::int64_t piece =
        std::max(parallel ? kParallelLoopMin : kFirstRetreatPiece, searched / kRetreatPieceGrowth);
    const std::int64_t end = std::min(n_retreating, searched + piece);
    search(searched, end, 0.0);
    searched = end;
    gather_bad();
    blocked = searched < n_retreating && first_free(bad) > 1.0;
  }
  // The pairs touching at the start of the step: those of the spheres searched are among
  // their candidates (a pair of two of them, or of one of them with a sphere outside the
  // group, was looked at from the same side as along the whole path).
  if (blocked) {
    for (Found& f : found) f.with_intervals = false;
    search(searched, n_retreating, 1.0);
  }
  std::vector<Candidate> candidates;
  for (Found& f : found) candidates.insert(candidates.end(), f.candidates.begin(), f.candidates.end());
  const double free_theta = blocked ? 2.0 : first_free(bad);  // above 1: none in [0, 1]
  const double theta = std::min(1.0, free_theta);

  Retreat<D> retreat{theta, free_theta <= 1.0, {}, {}};
  GroupSolution<D>& out = retreat.solution;
  if (with_candidates && retreat.free)
    for (const Candidate& k : candidates) retreat.candidates.push_back(k.pair);
  out.placed_at_contact = true;
  out.dissolves_bodies = true;
  out.result.converged = true;
  out.n_variables = static_cast<int>(clusters.size());
  for (const Candidate& k : candidates)
    if (std::abs((k.base - theta * k.drift).norm() / k.sigma - 1.0) <= eps_c) out.contacts.push_back(k.pair);
  // In pair order, not in the order the searches above happened to find them.
  std::sort(out.contacts.begin(), out.contacts.end(), pair_less<SpherePair>);
  for (const auto& cluster_and_body : clusters) {
    const int c = cluster_and_body.first;  // not a structured binding: clang 14 cannot capture one in a lambda
    auto move_back = [&](int i) {
      const Vec<D> shift = -ctx.step_shift[i] - theta * ctx.flight[c];
      if (shift == Vec<D>::Zero()) return;
      out.spheres.push_back(i);
      out.shift.push_back(shift);
    };
    for_each_prefetched(s.clusters[c].members, move_back, ctx.step_shift);
  }
  return retreat;
}

template Retreat<2> retreat_group<2>(const StepView<2>&, const CollisionGroup&, bool);
template Retreat<3> retreat_group<3>(const StepView<3>&, const CollisionGroup&, bool);

}  // namespace ballagg
