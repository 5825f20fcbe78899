// The retreat of the time-stepping engine (retreat.hpp) against a brute force over all
// pairs: on random groups of small clusters that flew into each other, among spheres that
// stay where they are (some of them in the group's starting place), the retreat fraction,
// whether it is free, and the pairs left touching are those of every pair looked at.
// The retreat's searches (cell lists along the paths, the partners of each cluster, the
// paths searched in pieces and given up once no instant is left free) must not lose any.
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "support.hpp"

#include "ballagg/engines/time_stepping/retreat.hpp"

namespace ballagg {
namespace {

struct ExpectedRetreat {
  double theta;
  bool free;
  std::set<std::pair<int, int>> contacts;
};

// Every pair of a sphere of the group with a sphere of another cluster (the group's clusters
// all small, so all searched): the open interval of theta where it is too close, and
// whether it touches (within eps_c) at the theta found. The spheres start their retreat
// where they are (no minimisation moved them in this step), those outside stay there.
template <int D>
ExpectedRetreat brute_force_retreat(const State<D>& s, const std::vector<Vec<D>>& x, const std::vector<Vec<D>>& flight,
                                    const std::set<int>& group, const DahaParameters& p) {
  const double tolerance = retreat_tolerance(p);
  struct Pair {
    int i, j;
    Vec<D> base, drift;
    double sigma;
  };
  std::vector<Pair> pairs;
  for (int i = 0; i < s.n_spheres(); ++i) {
    const int ci = s.spheres.cluster[i];
    if (!group.count(ci)) continue;
    for (int j = 0; j < s.n_spheres(); ++j) {
      const int cj = s.spheres.cluster[j];
      const bool member = group.count(cj) > 0;
      if (cj == ci || (member && j < i)) continue;
      const Vec<D> drift = member ? Vec<D>(flight[ci] - flight[cj]) : flight[ci];
      pairs.push_back({i, j, s.box.separation(x[i], x[j]), drift, s.spheres.radius[i] + s.spheres.radius[j]});
    }
  }
  std::vector<std::pair<double, double>> bad;
  for (const Pair& q : pairs) {
    double too_near = q.sigma * (1.0 - tolerance);
    if (group.count(s.spheres.cluster[q.j])) too_near = std::min(too_near, (q.base - q.drift).norm());
    const double a = q.drift.squaredNorm(), b = q.base.dot(q.drift), c = q.base.squaredNorm() - too_near * too_near;
    if (a == 0.0) {
      if (c < 0.0) bad.push_back({-1.0, 2.0});
      continue;
    }
    const double disc = b * b - a * c;
    if (disc > 0.0) bad.push_back({(b - std::sqrt(disc)) / a, (b + std::sqrt(disc)) / a});
  }
  std::sort(bad.begin(), bad.end());
  double free_theta = 0.0;
  for (const auto& [lo, hi] : bad)
    if (lo < free_theta && hi > free_theta) free_theta = hi;
  ExpectedRetreat out{std::min(1.0, free_theta), free_theta <= 1.0, {}};
  for (const Pair& q : pairs)
    if (std::abs((q.base - out.theta * q.drift).norm() / q.sigma - 1.0) <= p.eps_c) out.contacts.insert({q.i, q.j});
  return out;
}

template <int D>
Vec<D> random_direction(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Vec<D> v;
  for (int a = 0; a < D; ++a) v[a] = normal(rng);
  return v.normalized();
}

template <int D>
bool clear_of(const Vec<D>& x, const std::vector<Vec<D>>& others, double distance) {
  for (const Vec<D>& o : others)
    if ((o - x).norm() <= distance) return false;
  return true;
}

template <int D>
bool retreat_matches_brute_force(std::vector<testing::Ball<D>> balls, int n_group_spheres,
                                 const std::vector<Vec<D>>& cluster_flight, double length, Boundary boundary,
                                 int& free_count, int& blocked_count);

// One random group: 3-6 chains of 2-8 touching spheres (radius 0.5) whose starts are free
// of each other, flying towards a common point so that they end deep inside each other,
// among spheres that stay where they are, free of each other and of the group's ends (some
// of them where the group started). Returns whether the retreat matched the brute force,
// and counts the groups with and without a free instant.
template <int D>
bool retreat_matches_brute_force(std::mt19937& rng, int& free_count, int& blocked_count) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double length = D == 2 ? 40.0 : 24.0;
  Vec<D> centre = Vec<D>::Constant(0.5 * length);
  std::vector<testing::Ball<D>> balls;
  std::vector<Vec<D>> starts, ends, cluster_flight;
  const int n_clusters = 3 + static_cast<int>(4 * unit(rng));
  for (int k = 0; k < n_clusters; ++k) {
    std::vector<Vec<D>> chain;
    Vec<D> anchor;
    do anchor = centre + (D == 2 ? 6.0 : 4.0) * unit(rng) * random_direction<D>(rng);
    while (!clear_of<D>(anchor, starts, 1.0));
    chain.push_back(anchor);
    const int size = 2 + static_cast<int>(7 * unit(rng));
    for (int tries = 0; static_cast<int>(chain.size()) < size && tries < 100; ++tries) {
      const Vec<D> next = chain.back() + random_direction<D>(rng);
      if (clear_of<D>(next, chain, 0.999) && clear_of<D>(next, starts, 1.0)) chain.push_back(next);
    }
    const Vec<D> flight = (0.6 + 0.8 * unit(rng)) * (centre - anchor) + random_direction<D>(rng);
    for (const Vec<D>& x : chain) {
      starts.push_back(x);
      ends.push_back(x + flight);
      balls.push_back({x + flight, Vec<D>::Zero(), 0.5, 1.0, k});
    }
    cluster_flight.push_back(flight);
  }
  const int n_group_spheres = static_cast<int>(balls.size());
  std::vector<Vec<D>> outside;
  const int outside_tries = static_cast<int>((D == 2 ? 400 : 500) * unit(rng) * unit(rng));  // often few
  for (int tries = 0; tries < outside_tries; ++tries) {
    const Vec<D> x = centre + (D == 2 ? 10.0 : 6.0) * Vec<D>::NullaryExpr([&] { return 2.0 * unit(rng) - 1.0; });
    if (clear_of<D>(x, outside, 1.0) && clear_of<D>(x, ends, 1.0)) outside.push_back(x);
  }
  for (const Vec<D>& x : outside) balls.push_back({x, Vec<D>::Zero(), 0.5, 1.0, -1});
  return retreat_matches_brute_force<D>(balls, n_group_spheres, cluster_flight, length, Boundary::walls, free_count,
                                        blocked_count);
}

// The retreat of a group against the brute force. balls: where the spheres are at the end
// of the step, the group's first (n_group_spheres of them, Ball::cluster the index of
// their cluster's flight in cluster_flight), then those outside (cluster -1), which stay.
template <int D>
bool retreat_matches_brute_force(std::vector<testing::Ball<D>> balls, int n_group_spheres,
                                 const std::vector<Vec<D>>& cluster_flight, double length, Boundary boundary,
                                 int& free_count, int& blocked_count) {
  // The retreat reads where the spheres are from the context, not from the state; the
  // state, which must be free of overlaps, holds them on a lattice.
  std::vector<Vec<D>> positions;
  const int side = static_cast<int>(std::ceil(std::pow(static_cast<double>(balls.size()), 1.0 / D)));
  for (std::size_t k = 0; k < balls.size(); ++k) {
    positions.push_back(balls[k].x);
    std::size_t rest = k;
    for (int a = 0; a < D; ++a, rest /= side) balls[k].x[a] = 1.0 + static_cast<double>(rest % side);
  }
  const State<D> s = testing::make_state<D>(length, boundary, balls);

  const int n = s.n_spheres();
  const int n_ids = static_cast<int>(s.clusters.size());
  std::vector<Vec<D>> step_shift(n, Vec<D>::Zero()), flight(n_ids, Vec<D>::Zero());
  std::set<int> group;
  for (int i = 0; i < n_group_spheres; ++i) {
    group.insert(s.spheres.cluster[i]);
    flight[s.spheres.cluster[i]] = cluster_flight[static_cast<std::size_t>(balls[i].cluster)];
  }
  MovableCellList<D> cells(s.box, 4.0 * s.max_radius(), n);
  cells.build(positions);
  const StepBodies bodies(n_ids);
  const AdhesiveSet S(n_ids);
  const AdhesiveLinks links(n);
  const TimeSteppingSettings settings;
  const StepView<D> ctx{.state = s,
                         .positions = positions,
                         .step_shift = step_shift,
                         .flight = flight,
                         .bodies = bodies,
                         .cells = cells,
                         .cell_slack = cells.cell_size() - 2.0 * s.max_radius(),
                         .S = S,
                         .links = links,
                         .settings = settings,
                         .length_scale = 1.0,
                         .delta_w = 4.0,
                         .mean_mass = 1.0};
  CollisionGroup g;
  g.bodies.assign(group.begin(), group.end());

  const Retreat<D> retreat = retreat_group(ctx, g);
  const ExpectedRetreat expected = brute_force_retreat<D>(s, positions, flight, group, settings.daha);
  std::set<std::pair<int, int>> contacts;
  for (const SpherePair& p : retreat.solution.contacts) contacts.insert({p.i, p.j});
  (retreat.free ? free_count : blocked_count)++;
  EXPECT_EQ(retreat.free, expected.free);
  EXPECT_NEAR(retreat.theta, expected.theta, 1e-12);
  EXPECT_EQ(contacts, expected.contacts);
  EXPECT_EQ(retreat.solution.contacts.size(), contacts.size()) << "a pair listed twice";
  return retreat.free == expected.free && std::abs(retreat.theta - expected.theta) <= 1e-12 &&
         contacts == expected.contacts;
}

template <int D>
void retreats_match_the_brute_force(int trials) {
  std::mt19937 rng(D == 2 ? 5 : 6);
  int free_count = 0, blocked_count = 0;
  for (int t = 0; t < trials; ++t) ASSERT_TRUE(retreat_matches_brute_force<D>(rng, free_count, blocked_count)) << "trial " << t;
  // Both outcomes are exercised, the blocked one with groups of more spheres than the
  // first piece of paths searched.
  EXPECT_GE(free_count, trials / 10);
  EXPECT_GE(blocked_count, trials / 10);
}

TEST(Retreat, MatchesABruteForceOverAllPairs2D) { retreats_match_the_brute_force<2>(300); }
TEST(Retreat, MatchesABruteForceOverAllPairs3D) { retreats_match_the_brute_force<3>(100); }

// A crowd: kPartnerGridClusters and more monomers (radius 0.5), free of each other at the
// start of the step, each flying up to 3 in a random direction, among spheres at rest free
// of the monomers' ends (some in their starting places). A group this large finds its
// partners through the grid of swept boxes; the retreat must still match the brute force.
template <int D>
bool crowd_retreat_matches_brute_force(std::mt19937& rng, Boundary boundary, int& free_count, int& blocked_count) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double length = D == 2 ? 36.0 : 15.0;
  // Starts and ends within the walls (3 from them), images apart with periodic faces.
  auto anywhere = [&] { return Vec<D>(Vec<D>::NullaryExpr([&] { return 3.0 + (length - 6.0) * unit(rng); })); };
  std::vector<Vec<D>> starts, ends, cluster_flight;
  std::vector<testing::Ball<D>> balls;
  for (int tries = 0; tries < 20000 && static_cast<int>(starts.size()) < 320; ++tries) {
    const Vec<D> start = anywhere();
    if (!clear_of<D>(start, starts, 1.0)) continue;
    const Vec<D> flight = 3.0 * unit(rng) * random_direction<D>(rng);
    starts.push_back(start);
    ends.push_back(start + flight);
    balls.push_back({Vec<D>(start + flight), Vec<D>::Zero(), 0.5, 1.0, static_cast<std::int64_t>(cluster_flight.size())});
    cluster_flight.push_back(flight);
  }
  EXPECT_GE(starts.size(), 300u);
  const int n_group_spheres = static_cast<int>(balls.size());
  std::vector<Vec<D>> outside;
  for (int tries = 0; tries < 300; ++tries) {
    const Vec<D> x = anywhere();
    if (clear_of<D>(x, outside, 1.0) && clear_of<D>(x, ends, 1.0)) outside.push_back(x);
  }
  for (const Vec<D>& x : outside) balls.push_back({x, Vec<D>::Zero(), 0.5, 1.0, -1});
  return retreat_matches_brute_force<D>(balls, n_group_spheres, cluster_flight, length, boundary, free_count,
                                        blocked_count);
}

template <int D>
void crowd_retreats_match_the_brute_force(int trials) {
  std::mt19937 rng(D == 2 ? 15 : 16);
  int free_count = 0, blocked_count = 0;
  for (int t = 0; t < trials; ++t) {
    const Boundary boundary = t % 2 == 0 ? Boundary::walls : Boundary::periodic;
    ASSERT_TRUE(crowd_retreat_matches_brute_force<D>(rng, boundary, free_count, blocked_count)) << "trial " << t;
  }
}

TEST(Retreat, OfACrowdMatchesABruteForceOverAllPairs2D) { crowd_retreats_match_the_brute_force<2>(6); }
TEST(Retreat, OfACrowdMatchesABruteForceOverAllPairs3D) { crowd_retreats_match_the_brute_force<3>(4); }

// A group of three clusters: the giant G (still, far away), A (a row of `a_size` spheres
// that flew up by 2) and the monomer B (flew down by 2 into A's first sphere, 0.2 from its
// centre at the end of the step). A sphere O outside the group lies beside A's last
// sphere, 0.6 to its side and 1 below where A ended: A's way back passes O. B alone needs
// the group back by theta_B; O is too close to A's last sphere for theta in (theta_lo,
// theta_O), which holds theta_B. Returns the retreat fraction found.
double retreat_of_a_row_past_an_outside_sphere(int a_size) {
  constexpr double y_end = 10.0;
  std::vector<testing::Ball<2>> balls;
  for (int k = 0; k < a_size + 10; ++k) balls.push_back({Vec<2>(5.0 + k, 40.0), Vec<2>::Zero(), 0.5, 1.0, 0});  // G
  for (int k = 0; k < a_size; ++k) balls.push_back({Vec<2>(5.0 + k, y_end), Vec<2>::Zero(), 0.5, 1.0, 1});     // A
  balls.push_back({Vec<2>(5.0, y_end + 0.2), Vec<2>::Zero(), 0.5, 1.0, 2});                                  // B
  balls.push_back({Vec<2>(5.0 + (a_size - 1) + 0.6, y_end - 1.0), Vec<2>::Zero(), 0.5, 1.0, -1});            // O
  // The state, free of overlaps, holds the spheres on a lattice; the retreat reads where
  // they are from the context.
  std::vector<Vec<2>> positions;
  for (std::size_t k = 0; k < balls.size(); ++k) {
    positions.push_back(balls[k].x);
    balls[k].x = Vec<2>(1.0 + static_cast<double>(k % 90), 60.0 + static_cast<double>(k / 90));
  }
  const State<2> s = testing::make_state<2>(100.0, Boundary::walls, balls);
  const int n_ids = static_cast<int>(s.clusters.size());
  const int g = s.spheres.cluster[0], a = s.spheres.cluster[a_size + 10], b = s.spheres.cluster[2 * a_size + 10];
  std::vector<Vec<2>> step_shift(s.n_spheres(), Vec<2>::Zero()), flight(n_ids, Vec<2>::Zero());
  flight[a] = Vec<2>(0.0, 2.0);
  flight[b] = Vec<2>(0.0, -2.0);
  MovableCellList<2> cells(s.box, 4.0 * s.max_radius(), s.n_spheres());
  cells.build(positions);
  const StepBodies bodies(n_ids);
  const AdhesiveSet S(n_ids);
  const AdhesiveLinks links(s.n_spheres());
  const TimeSteppingSettings settings;
  const StepView<2> ctx{.state = s,
                         .positions = positions,
                         .step_shift = step_shift,
                         .flight = flight,
                         .bodies = bodies,
                         .cells = cells,
                         .cell_slack = cells.cell_size() - 2.0 * s.max_radius(),
                         .S = S,
                         .links = links,
                         .settings = settings,
                         .length_scale = 1.0,
                         .delta_w = 4.0,
                         .mean_mass = 1.0};
  CollisionGroup group;
  group.bodies = {g, a, b};
  const Retreat<2> retreat = retreat_group(ctx, group);
  EXPECT_TRUE(retreat.free);
  return retreat.theta;
}

// A cluster of the group other than its largest is searched along its way back for spheres
// outside the group up to kOutsideSearchedClusterSize spheres, and not beyond (retreat.hpp).
TEST(Retreat, SearchesOutsideTheGroupOnlyAlongThePathsOfClustersUpToTheSizeSet) {
  const double too_near = 1.0 - retreat_tolerance(TimeSteppingSettings{}.daha);  // radii 0.5
  const double theta_b = (too_near - 0.2) / 4.0;  // B and A part at 4 per unit of theta
  // O and A's last sphere: 0.6 apart sideways, 1 - 2 theta apart along the flight.
  const double theta_o = (1.0 + std::sqrt(too_near * too_near - 0.36)) / 2.0;
  ASSERT_LT((1.0 - std::sqrt(too_near * too_near - 0.36)) / 2.0, theta_b);  // O's interval holds theta_B
  EXPECT_NEAR(retreat_of_a_row_past_an_outside_sphere(kOutsideSearchedClusterSize), theta_o, 1e-12);
  EXPECT_NEAR(retreat_of_a_row_past_an_outside_sphere(kOutsideSearchedClusterSize + 1), theta_b, 1e-12);
}

}  // namespace
}  // namespace ballagg
