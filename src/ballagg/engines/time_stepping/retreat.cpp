#include "ballagg/engines/time_stepping/retreat.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "ballagg/collision/crossing.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/engines/time_stepping/sorted_ids.hpp"
#include "ballagg/spatial/swept_box_grid.hpp"

namespace ballagg {
namespace {

// The open interval of retreat fractions theta where |base - theta * drift| < reach (empty:
// lo >= hi), not clipped to [0, 1]: an interval containing 0 or 1 says so.
template <int D>
std::pair<double, double> too_close(const Vec<D>& base, const Vec<D>& drift, double reach) {
  constexpr std::pair<double, double> kNever{1.0, 0.0}, kAlways{-1.0, 2.0};
  const crossing::Quadratic q = crossing::quadratic(base, Vec<D>(-drift), reach);
  if (q.a == 0.0) return q.c < 0.0 ? kAlways : kNever;
  const double disc = crossing::discriminant(q);
  if (disc <= 0.0) return kNever;
  const crossing::Roots t = crossing::direct_roots(q, std::sqrt(disc));
  return {t.entry, t.exit};
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

// From this many clusters a group's partners are found among the clusters whose swept
// boxes share a cell (swept_box_grid.hpp) rather than by testing every pair of its
// clusters: the same partners, for a cost that follows the group's size instead of its
// square.
constexpr std::size_t kPartnerGridClusters = 256;

namespace {

// The search of one retreat, in named steps: which clusters of the group each retreating
// cluster can meet (partners), the pairs along each retreating sphere's path (look_around:
// with the partners' spheres, and with the spheres outside the group), the paths searched
// piece by piece until the verdict is known (search_paths), and the group moved back by
// the fraction found (solution).
//
// Only the pairs that the retreat can bring within contact distance are looked at. A
// sphere i moves back along its cluster's flight, a segment: a sphere outside the group
// (which stays where it is) matters only within a contact distance of that segment, and a
// sphere of another cluster o of the group only within one of the segment of i's motion
// relative to o. So: a narrow search around each such segment (wide enough for the pairs
// left touching, eps_c, and for the cell list's slack), and o's spheres listed directly
// when o is small, none at all when o's bounding sphere stays away.
template <int D>
class RetreatSearch {
 public:
  RetreatSearch(const StepView<D>& ctx, const CollisionGroup& g);
  Retreat<D> run(bool with_candidates);

 private:
  struct Candidate {
    SpherePair pair;
    Vec<D> base, drift;  // separation at theta: base - theta * drift
    double sigma;
  };
  // Per thread: the pairs looked at, and the retreat fractions where a pair is too close.
  // Their order does not matter: the intervals are sorted and the contacts put in pair
  // order, so the result does not depend on the number of threads.
  struct Found {
    std::vector<Candidate> candidates;
    std::vector<std::pair<double, double>> bad;
    bool with_intervals = true;  // false once the verdict is known: only the contacts are wanted
  };

  void list_small_clusters();
  void list_retreating();
  void list_partners();
  bool can_meet(std::size_t k, std::size_t m) const;
  void consider(Found& out, int i, int j, int bj) const;
  void look_around(Found& out, int i, std::size_t k, double from) const;
  void look_at_partner(Found& out, int i, std::size_t k, std::size_t m, double from) const;
  void look_outside(Found& out, int i, std::size_t k, double from) const;
  void search(std::int64_t begin, std::int64_t end, double from);
  double search_paths();
  Retreat<D> solution(double free_theta, bool with_candidates);

  const StepView<D>& ctx_;
  const State<D>& s_;
  const QueriedClusters<D> queried_;
  const std::vector<std::pair<std::int32_t, std::int32_t>>& clusters_;  // (cluster, body index) of the group
  const double tolerance_, eps_c_;
  // Beyond the largest reach of consider (that of the largest contact distance) a pair is
  // dropped before its radii are read, with the same outcome.
  const double beyond_every_reach2_;
  const GroupMarks marks_;
  const double contact_reach_;
  const std::vector<RetreatStart<D>> starts_;
  std::vector<Found> found_;
  // Where each member of the group's small clusters starts its retreat, in member order,
  // [listed_first_[k], listed_first_[k + 1]) for cluster k: a retreating sphere tries every
  // member of a small partner, and read from here, a member that cannot come near is passed
  // over at the cost of one test instead of reads of the scattered per-sphere arrays.
  std::vector<std::size_t> listed_first_;
  std::vector<Vec<D>> listed_start_;
  std::vector<std::vector<std::size_t>> partners_;             // per cluster k: the m it can meet
  std::vector<char> outside_searched_;                         // per cluster k: searched_against_outside
  std::vector<std::pair<std::int32_t, std::int32_t>> retreating_;  // (sphere, k) of the queried clusters
  bool parallel_ = false;
};

template <int D>
RetreatSearch<D>::RetreatSearch(const StepView<D>& ctx, const CollisionGroup& g)
    : ctx_(ctx),
      s_(ctx.state),
      queried_(ctx, g, std::numeric_limits<int>::max()),
      clusters_(queried_.clusters),
      tolerance_(retreat_tolerance(ctx.settings.daha)),
      eps_c_(ctx.settings.daha.eps_c),
      beyond_every_reach2_(beyond_squared(2.0 * s_.max_radius() * (1.0 + kCandidateReach * eps_c_))),
      marks_(s_.spheres.cluster, s_.clusters.size(), queried_.clusters),
      contact_reach_(2.0 * s_.max_radius() * (1.0 + ctx.settings.daha.eps_c)),
      starts_(retreat_starts(ctx, clusters_)),
      found_(max_threads()) {
  list_small_clusters();
  list_retreating();
}

template <int D>
void RetreatSearch<D>::list_small_clusters() {
  listed_first_.assign(clusters_.size() + 1, 0);
  for (std::size_t k = 0; k < clusters_.size(); ++k) {
    const Cluster<D>& cluster = s_.clusters[clusters_[k].first];
    if (cluster.size() <= kListedClusterSize)
      for (int j : cluster.members) listed_start_.push_back(ctx_.positions[j] - ctx_.step_shift[j]);
    listed_first_[k + 1] = listed_start_.size();
  }
}

// The partners of each queried cluster, and its spheres, which retreat.
template <int D>
void RetreatSearch<D>::list_retreating() {
  outside_searched_.resize(clusters_.size());
  for (std::size_t k = 0; k < clusters_.size(); ++k) outside_searched_[k] = searched_against_outside(s_, clusters_[k].first);
  list_partners();
  for (std::size_t k = 0; k < clusters_.size(); ++k) {
    const int c = clusters_[k].first;
    if (queried_(c))
      for (int i : s_.clusters[c].members) retreating_.push_back({i, static_cast<std::int32_t>(k)});
  }
  // A large group's searches are shared among the threads.
  parallel_ = static_cast<std::int64_t>(retreating_.size()) >= kParallelLoopMin;
}

// The clusters of the group each queried cluster can meet (can_meet), in increasing order.
// In a large group, only those whose swept boxes share a cell are tested: the box of a
// cluster holds its bounding sphere along its way back, widened by a contact distance
// (more than the half that makes the boxes of two clusters that can meet overlap).
template <int D>
void RetreatSearch<D>::list_partners() {
  const std::size_t n = clusters_.size();
  partners_.resize(n);
  auto queried = [&](std::size_t k) { return queried_(clusters_[k].first); };
  if (n < kPartnerGridClusters) {
    for (std::size_t k = 0; k < n; ++k)
      if (queried(k))
        for (std::size_t m = 0; m < n; ++m)
          if (m != k && can_meet(k, m)) partners_[k].push_back(m);
    return;
  }
  std::vector<SweptBox<D>> boxes(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec<D>& from = starts_[k].centre;
    const Vec<D> to = from - ctx_.flight[clusters_[k].first];
    const Vec<D> widen = Vec<D>::Constant(starts_[k].radius + contact_reach_);
    boxes[k] = {Vec<D>(from.cwiseMin(to) - widen), Vec<D>(from.cwiseMax(to) + widen)};
  }
  const SweptBoxGrid<D> grid(s_.box, boxes);
  std::vector<std::int32_t> candidates;
  for (std::size_t k = 0; k < n; ++k) {
    if (!queried(k)) continue;
    candidates.clear();
    grid.for_each_candidate(k, [&](std::int32_t m) { candidates.push_back(m); });
    sort_unique(candidates);
    for (std::int32_t m : candidates)
      if (static_cast<std::size_t>(m) != k && can_meet(k, static_cast<std::size_t>(m))) partners_[k].push_back(m);
  }
}

// Whether clusters k and m of the group can meet: their bounding spheres come within a
// contact distance along the relative flight. Tested per cluster pair first, since a large
// group is a chain of clusters most of which are far from each other.
template <int D>
bool RetreatSearch<D>::can_meet(std::size_t k, std::size_t m) const {
  const Vec<D> relative_flight = ctx_.flight[clusters_[k].first] - ctx_.flight[clusters_[m].first];
  const Vec<D> between = s_.box.separation(starts_[k].centre, starts_[m].centre);
  return distance_to_segment<D>(between, -relative_flight) <= starts_[k].radius + starts_[m].radius + contact_reach_;
}

// Sphere i of the group and sphere j (bj: the index of its body in the group, -1 outside).
// Kept only if it can touch (within eps_c) at some theta in [0, 1]; a pair that stays
// farther apart than that all along the segment is not too close at any theta in [0, 1]
// either: its interval, if any, lies beyond theta = 1 and changes neither the theta that
// first_free finds in [0, 1] nor whether there is one.
template <int D>
void RetreatSearch<D>::consider(Found& out, int i, int j, int bj) const {
  const int ci = s_.spheres.cluster[i], cj = s_.spheres.cluster[j];
  const bool member = bj >= 0;
  // The retreat starts where free flight put the group (this step's minimisations
  // undone); a sphere outside the group stays where it is now.
  const Vec<D> base = s_.box.separation(ctx_.positions[i] - ctx_.step_shift[i],
                                        member ? Vec<D>(ctx_.positions[j] - ctx_.step_shift[j]) : ctx_.positions[j]);
  const Vec<D> drift = member ? Vec<D>(ctx_.flight[ci] - ctx_.flight[cj]) : ctx_.flight[ci];
  const double closest2 = squared_distance_to_segment<D>(Vec<D>::Zero(), base, -drift);
  if (closest2 > beyond_every_reach2_) return;
  const double sigma = s_.spheres.radius[i] + s_.spheres.radius[j];
  const double reach = sigma * (1.0 + kCandidateReach * eps_c_);
  if (closest2 > reach * reach) return;
  if (out.with_intervals) {
    double too_near = sigma * (1.0 - tolerance_);
    // A pair of the group that overlaps at theta = 1 (by up to eps_c, left by the last
    // step) is held to that, never made worse.
    if (member) too_near = std::min(too_near, (base - drift).norm());
    const auto interval = too_close<D>(base, drift, too_near);
    if (interval.first < interval.second && interval.second > 0.0) out.bad.push_back(interval);
  }
  out.candidates.push_back({{std::min(i, j), std::max(i, j), 0.0}, base, drift, sigma});
}

// The pairs of one retreating sphere i of the group's k-th cluster along the part of its
// path from the retreat fraction `from` to 1 (0: the whole path; 1: its starting point,
// the start of the step). With from = 0 every offset below is exactly the whole path's.
template <int D>
void RetreatSearch<D>::look_around(Found& out, int i, std::size_t k, double from) const {
  for (std::size_t m : partners_[k]) look_at_partner(out, i, k, m, from);
  if (outside_searched_[k]) look_outside(out, i, k, from);
}

template <int D>
void RetreatSearch<D>::look_at_partner(Found& out, int i, std::size_t k, std::size_t m, double from) const {
  const int c = clusters_[k].first;
  const double span = 1.0 - from;
  const Vec<D> start = ctx_.positions[i] - ctx_.step_shift[i];
  const int other = clusters_[m].first, other_body = clusters_[m].second;
  const Vec<D> relative_flight = ctx_.flight[c] - ctx_.flight[other];
  const Vec<D> to_centre = s_.box.separation(start, starts_[m].centre);
  if (distance_to_segment<D>(Vec<D>(to_centre - from * relative_flight), Vec<D>(-(span * relative_flight))) >
      starts_[m].radius + contact_reach_)
    return;
  const bool other_queried = queried_(other);  // then a pair is taken from its lower sphere id's side
  auto member = [&](int j) {
    if (!(other_queried && j < i)) consider(out, i, j, other_body);
  };
  if (s_.clusters[other].size() <= kListedClusterSize) {
    const MemberList& members = s_.clusters[other].members;
    const Vec<D>* member_start = listed_start_.data() + listed_first_[m];
    for (std::size_t q = 0; q < members.size(); ++q) {
      // consider()'s first test, to the bit: the same separation and drift.
      const Vec<D> base = s_.box.separation(start, member_start[q]);
      if (squared_distance_to_segment<D>(Vec<D>::Zero(), base, -relative_flight) > beyond_every_reach2_) continue;
      member(members[q]);
    }
    return;
  }
  // The spheres of o are where the step's minimisations moved them, up to its
  // longest_shift from their start.
  auto in_other = [&](int j) {
    if (s_.spheres.cluster[j] == other) member(j);
  };
  ctx_.cells.for_each_near_segment(Vec<D>(start - from * relative_flight), Vec<D>(-(span * relative_flight)),
                                   contact_reach_ + starts_[m].longest_shift + ctx_.cell_slack, in_other);
}

template <int D>
void RetreatSearch<D>::look_outside(Found& out, int i, std::size_t k, double from) const {
  const int c = clusters_[k].first;
  const double span = 1.0 - from;
  const Vec<D> start = ctx_.positions[i] - ctx_.step_shift[i];
  auto outside = [&](int j) {
    if (s_.spheres.cluster[j] != c && marks_.body_index(j) < 0) consider(out, i, j, -1);
  };
  ctx_.cells.for_each_near_segment(Vec<D>(start - from * ctx_.flight[c]), Vec<D>(-(span * ctx_.flight[c])),
                                   contact_reach_ + ctx_.cell_slack, outside);
}

// The paths of retreating spheres [begin, end), from the fraction `from`, on the threads
// for a large group.
template <int D>
void RetreatSearch<D>::search(std::int64_t begin, std::int64_t end, double from) {
#pragma omp parallel for schedule(dynamic, 64) if (parallel_)
  for (std::int64_t r = begin; r < end; ++r)
    look_around(found_[thread_index()], retreating_[r].first, static_cast<std::size_t>(retreating_[r].second), from);
}

// The paths are searched in pieces. When the intervals found so far leave no theta in
// [0, 1] free, no later piece can free one (an interval only takes instants away): the
// group goes back to the start of the step whatever the rest of its paths hold, and only
// the pairs touching there are still wanted, found around each sphere's starting point
// instead of along its path. Same result as searching every path, for less. Returns the
// first free theta (above 1: none in [0, 1]).
template <int D>
double RetreatSearch<D>::search_paths() {
  const std::int64_t n_retreating = static_cast<std::int64_t>(retreating_.size());
  std::vector<std::pair<double, double>> bad;
  auto gather_bad = [&] {
    for (Found& f : found_) {
      bad.insert(bad.end(), f.bad.begin(), f.bad.end());
      f.bad.clear();
    }
  };
  std::int64_t searched = 0;
  bool blocked = false;  // no theta in [0, 1] free, found before every path was searched
  while (searched < n_retreating && !blocked) {
    const std::int64_t piece =
        std::max(parallel_ ? kParallelLoopMin : kFirstRetreatPiece, searched / kRetreatPieceGrowth);
    const std::int64_t end = std::min(n_retreating, searched + piece);
    search(searched, end, 0.0);
    searched = end;
    gather_bad();
    blocked = searched < n_retreating && first_free(bad) > 1.0;
  }
  if (!blocked) return first_free(bad);
  // The pairs touching at the start of the step: those of the spheres searched are among
  // their candidates (a pair of two of them, or of one of them with a sphere outside the
  // group, was looked at from the same side as along the whole path).
  for (Found& f : found_) f.with_intervals = false;
  search(searched, n_retreating, 1.0);
  return 2.0;
}

// The group moved back by theta = min(1, free_theta), its pairs left touching as contacts.
template <int D>
Retreat<D> RetreatSearch<D>::solution(double free_theta, bool with_candidates) {
  std::vector<Candidate> candidates;
  for (Found& f : found_) candidates.insert(candidates.end(), f.candidates.begin(), f.candidates.end());
  const double theta = std::min(1.0, free_theta);
  Retreat<D> retreat{theta, free_theta <= 1.0, {}, {}};
  GroupSolution<D>& out = retreat.solution;
  if (with_candidates && retreat.free)
    for (const Candidate& k : candidates) retreat.candidates.push_back(k.pair);
  out.placed_at_contact = true;
  out.dissolves_bodies = true;
  out.result.converged = true;
  out.n_variables = static_cast<int>(clusters_.size());
  for (const Candidate& k : candidates)
    if (std::abs((k.base - theta * k.drift).norm() / k.sigma - 1.0) <= eps_c_) out.contacts.push_back(k.pair);
  // In pair order, not in the order the searches happened to find them.
  std::sort(out.contacts.begin(), out.contacts.end(), pair_less<SpherePair>);
  for (const auto& cluster_and_body : clusters_) {
    const int c = cluster_and_body.first;  // not a structured binding: clang 14 cannot capture one in a lambda
    auto move_back = [&](int i) {
      const Vec<D> shift = -ctx_.step_shift[i] - theta * ctx_.flight[c];
      if (shift == Vec<D>::Zero()) return;
      out.spheres.push_back(i);
      out.shift.push_back(shift);
    };
    for_each_prefetched(s_.clusters[c].members, move_back, ctx_.step_shift);
  }
  return retreat;
}

template <int D>
Retreat<D> RetreatSearch<D>::run(bool with_candidates) {
  const double free_theta = search_paths();
  return solution(free_theta, with_candidates);
}

}  // namespace

template <int D>
Retreat<D> retreat_group(const StepView<D>& ctx, const CollisionGroup& g, bool with_candidates) {
  RetreatSearch<D> search(ctx, g);
  return search.run(with_candidates);
}

template Retreat<2> retreat_group<2>(const StepView<2>&, const CollisionGroup&, bool);
template Retreat<3> retreat_group<3>(const StepView<3>&, const CollisionGroup&, bool);

}  // namespace ballagg
