// The parts of the time-stepping engine on their own: the near-pair list, the repair waves,
// the adhesive set and its groups, the bodies of a step, the group marks, and the
// minimiser's stopping rules and bonds.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>

#include <gtest/gtest.h>
#include <omp.h>

#include "support.hpp"

#include "ballagg/core/pair_index.hpp"
#include "ballagg/engines/time_stepping/adhesive_set.hpp"
#include "ballagg/engines/time_stepping/daha.hpp"
#include "ballagg/engines/time_stepping/group_marks.hpp"
#include "ballagg/engines/time_stepping/near_pairs.hpp"
#include "ballagg/engines/time_stepping/repair_waves.hpp"
#include "ballagg/engines/time_stepping/step_bodies.hpp"
#include "ballagg/spatial/movable_cell_list.hpp"

namespace ballagg {
namespace {

// The near-pair list against a brute-force search over all pairs, while clusters move by
// random amounts (some beyond the half skin, most not) and merge. With a giant, 85 % of
// the spheres are first joined into one cluster that drifts beyond the half skin at every
// step, as late in a run: its pairs are then listed from the side of the other spheres.
// The partial refreshes get a cell list that binned each sphere up to its slack (half the
// skin) away from where it is, as the engine's list kept from earlier steps does; or, with
// aged_list, a list binned at an earlier step (rebinned every fourth refresh), with the
// slack the farthest any sphere has moved since and the positions left unfilled, as the
// engine passes it to a refresh that queries few spheres (StepCells::for_queries).
template <int D>
void near_pairs_find_every_contact(Boundary boundary, bool giant = false, bool aged_list = false) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double length = D == 2 ? 30.0 : 12.0;
  std::vector<testing::Ball<D>> balls;
  for (int k = 0; k < 400; ++k) {
    testing::Ball<D> b;
    for (int a = 0; a < D; ++a) b.x[a] = 1.0 + (length - 2.0) * unit(rng);
    b.v.setZero();
    b.radius = 0.3 + 0.2 * unit(rng);
    bool free = true;
    for (const auto& other : balls) free = free && (other.x - b.x).norm() > other.radius + b.radius;
    if (free) balls.push_back(b);
  }
  State<D> s = testing::make_state<D>(length, boundary, balls);
  SortedCellList<D> cells(s.box, 1.5 * 2.0 * s.max_radius(), s.n_spheres());
  MovableCellList<D> kept(s.box, 1.5 * 2.0 * s.max_radius(), s.n_spheres());
  NearPairs<D> near(static_cast<int>(s.clusters.size()), cells.cell_size() - 2.0 * s.max_radius());
  const double slack = 0.5 * near.skin();
  std::vector<Vec<D>> binned_at(s.n_spheres());
  std::vector<Vec<D>> positions(s.n_spheres());
  for (int i = 1; giant && i < s.n_spheres() * 85 / 100; ++i) s.merge(0, i, 0.0);
  int lazy_steps = 0;  // steps in which only the listed pairs' positions were asked for
  int aged_refreshes = 0;
  for (int step = 0; step < 60; ++step) {
    const bool quiet = step % 5 == 4;  // nothing moves: no cluster is stale
    for (int c : quiet ? std::vector<int>{} : s.alive_clusters()) {
      Vec<D> du;
      for (int a = 0; a < D; ++a) du[a] = unit(rng) - 0.5;
      const bool far = (giant && s.spheres.cluster[0] == c) || unit(rng) < 0.1;  // the giant always
      du *= (far ? 0.6 : giant ? 0.01 : 0.05) * cells.cell_size() / du.norm();
      s.translate(c, du, 0.0);
      near.travelled(c, du.norm());
    }
    // As in the engine, positions are filled only when asked for: all of them with the
    // cell list, or those `need` names. Entries left NaN would lose contacts below.
    std::fill(positions.begin(), positions.end(), Vec<D>::Constant(std::nan("")));
    auto all_positions = [&]() -> const SortedCellList<D>& {
      for (int i = 0; i < s.n_spheres(); ++i) positions[i] = s.position(i, 0.0);
      cells.build(positions);
      return cells;
    };
    auto binned_nearby = [&](std::size_t) -> typename NearPairCells<D>::Binned {
      if (aged_list) {
        if (aged_refreshes++ % 4 == 0) {
          for (int i = 0; i < s.n_spheres(); ++i) binned_at[i] = s.position(i, 0.0);
          kept.build(binned_at);
        }
        double drift = 0.0;
        for (int i = 0; i < s.n_spheres(); ++i)
          drift = std::max(drift, s.box.separation(s.position(i, 0.0), binned_at[i]).norm());
        return {kept, drift, true};
      }
      for (int i = 0; i < s.n_spheres(); ++i) {
        positions[i] = s.position(i, 0.0);
        Vec<D> off;
        for (int a = 0; a < D; ++a) off[a] = unit(rng) - 0.5;
        binned_at[i] = positions[i] + slack * off / off.norm();  // the farthest allowed
        if (s.box.periodic()) binned_at[i] = s.box.wrap(binned_at[i]);
        else binned_at[i] = binned_at[i].cwiseMax(0.0).cwiseMin(s.box.length);
      }
      kept.build(binned_at);
      return {kept, slack};
    };
    auto need = [&](const std::vector<std::int32_t>& ids) {
      ++lazy_steps;
      for (std::int32_t i : ids) positions[i] = s.position(i, 0.0);
    };
    const std::vector<SpherePair> found = near.contacts(s, positions, {all_positions, binned_nearby}, need);
    std::vector<std::pair<int, int>> expected, got;
    for (int i = 0; i < s.n_spheres(); ++i)
      for (int j = i + 1; j < s.n_spheres(); ++j) {
        const double sigma = s.spheres.radius[i] + s.spheres.radius[j];
        if (s.spheres.cluster[i] != s.spheres.cluster[j] &&
            s.box.separation(s.position(i, 0.0), s.position(j, 0.0)).norm() <= sigma)
          expected.push_back({i, j});
      }
    for (const SpherePair& p : found) got.push_back({p.i, p.j});
    ASSERT_EQ(got, expected) << "step " << step;
    // The promise of listed(): every cluster moved by what is left of its budget (skin / 2
    // less its travel), the spheres that now touch another cluster are all listed. (Every
    // fifth step: the next ones list every cluster again, and the quiet ones stay lazy.)
    for (int c : step % 5 == 2 ? s.alive_clusters() : std::vector<int>{}) {
      Vec<D> du;
      for (int a = 0; a < D; ++a) du[a] = unit(rng) - 0.5;
      du *= (0.5 * near.skin() - near.travel(c)) / du.norm();
      s.translate(c, du, 0.0);
      near.travelled(c, du.norm());
    }
    for (int i = 0; i < s.n_spheres(); ++i)
      for (int j = i + 1; j < s.n_spheres(); ++j) {
        const double sigma = s.spheres.radius[i] + s.spheres.radius[j];
        if (s.spheres.cluster[i] != s.spheres.cluster[j] &&
            s.box.separation(s.position(i, 0.0), s.position(j, 0.0)).norm() <= sigma) {
          ASSERT_TRUE(near.listed(i) && near.listed(j)) << "step " << step << ": " << i << ", " << j;
        }
      }
    for (std::size_t k = 0; k < found.size(); k += 3) {  // some contacts merge their clusters
      const int ci = s.spheres.cluster[found[k].i], cj = s.spheres.cluster[found[k].j];
      if (ci != cj) near.merged(ci, cj, s.merge(found[k].i, found[k].j, 0.0));
    }
  }
  EXPECT_GE(near.full_scans(), 1);
  EXPECT_GE(near.partial_scans(), 10);
  EXPECT_GE(lazy_steps, 10);
  if (aged_list) {
    EXPECT_EQ(aged_refreshes, near.partial_scans());
  }
  if (giant) {
    EXPECT_GE(near.outside_scans(), 20);
  } else {
    EXPECT_LT(s.n_clusters(), 380);
  }
}

TEST(NearPairs, EveryContactIsFoundAsByABruteForceSearch) {
  near_pairs_find_every_contact<2>(Boundary::walls);
  near_pairs_find_every_contact<2>(Boundary::periodic);
  near_pairs_find_every_contact<3>(Boundary::periodic);
}

TEST(NearPairs, TheDriftingGiantsPairsAreFoundFromTheOtherSpheres) {
  near_pairs_find_every_contact<2>(Boundary::walls, true);
  near_pairs_find_every_contact<2>(Boundary::periodic, true);
  near_pairs_find_every_contact<3>(Boundary::periodic, true);
}

// Late in a run the engine does not bin a drifted giant again for a refresh that queries
// a few spheres: the queries look wider by the drift, and read the positions from the state.
TEST(NearPairs, AListBinnedStepsAgoIsQueriedWiderWithPositionsFromTheState) {
  near_pairs_find_every_contact<2>(Boundary::walls, true, true);
  near_pairs_find_every_contact<2>(Boundary::periodic, true, true);
  near_pairs_find_every_contact<3>(Boundary::periodic, true, true);
  near_pairs_find_every_contact<2>(Boundary::walls, false, true);
}

// A partial refresh that queries around sphere A must list its near pair with B although
// the cell list binned B by the full slack away, outside the 3 x 3 cells around A: the
// cells are 1.5 wide (skin 0.5, slack 0.25), A sits just inside the left edge of its
// cell, B 1.495 to its left and binned 0.25 further. Once both move 0.249 towards each
// other (within the half skin, no refresh) they touch, and only the listed pair says so.
TEST(NearPairs, APartialRefreshLooksAsFarAsTheCellListsSlack) {
  std::vector<testing::Ball<2>> balls(2);
  balls[0].x = Vec<2>(3.01, 5.25);   // A
  balls[1].x = Vec<2>(1.515, 5.25);  // B
  for (double x : {7.5, 8.7, 9.9, 11.1})  // far away: enough spheres for cells 1.5 wide
    for (int k = 0; k < 10; ++k) balls.push_back({Vec<2>(x, 0.6 + 1.2 * k), Vec<2>::Zero()});
  for (auto& b : balls) {
    b.v.setZero();
    b.radius = 0.5;
  }
  State<2> s = testing::make_state<2>(12.0, Boundary::walls, balls);
  SortedCellList<2> cells(s.box, 1.5, s.n_spheres());
  MovableCellList<2> kept(s.box, 1.5, s.n_spheres());
  ASSERT_DOUBLE_EQ(cells.cell_size(), 1.5);
  NearPairs<2> near(static_cast<int>(s.clusters.size()), cells.cell_size() - 1.0);
  const double slack = 0.5 * near.skin();
  std::vector<Vec<2>> positions(s.n_spheres());
  auto fill = [&] {
    for (int i = 0; i < s.n_spheres(); ++i) positions[i] = s.position(i, 0.0);
  };
  auto rebuilt = [&]() -> const SortedCellList<2>& {
    fill();
    cells.build(positions);
    return cells;
  };
  auto binned_away = [&](std::size_t) -> NearPairCells<2>::Binned {
    fill();
    std::vector<Vec<2>> binned_at = positions;
    binned_at[1].x() -= slack;
    kept.build(binned_at);
    return {kept, slack};
  };
  auto need = [&](const std::vector<std::int32_t>&) { fill(); };
  const int a = s.spheres.cluster[0], b = s.spheres.cluster[1];
  EXPECT_TRUE(near.contacts(s, positions, {rebuilt, binned_away}, need).empty());  // the first: a full scan
  near.travelled(a, 0.3);  // A is stale, B is not
  EXPECT_TRUE(near.contacts(s, positions, {rebuilt, binned_away}, need).empty());
  EXPECT_EQ(near.full_scans(), 1);
  EXPECT_EQ(near.partial_scans(), 1);
  s.translate(a, Vec<2>(-0.249, 0.0), 0.0);
  near.travelled(a, 0.249);
  s.translate(b, Vec<2>(0.249, 0.0), 0.0);
  near.travelled(b, 0.249);
  const std::vector<SpherePair> touching = near.contacts(s, positions, {rebuilt, binned_away}, need);
  ASSERT_EQ(touching.size(), 1u);
  EXPECT_EQ(std::make_pair(touching[0].i, touching[0].j), std::make_pair(0, 1));
}

// some images of them).
template <int D>
bool regions_meet(const Region<D>& a, const Region<D>& b, const Box<D>& box) {
  for (int k = 0; k < D; ++k) {
    bool overlap = false;
    const int images = box.periodic() ? 3 : 0;
    for (int m = -images; m <= images; ++m)
      overlap = overlap || (a.lo[k] <= b.hi[k] + m * box.length && b.lo[k] + m * box.length <= a.hi[k]);
    if (!overlap) return false;
  }
  return true;
}

// waves_of_regions: every region once, and a region meeting an earlier one is in a later
// wave (so the regions of one wave never meet, and running a wave at once cannot change
// what the order gives). Regions of mixed sizes, some wider than the tiles, some unfolded
// beyond the box in a periodic one.
template <int D>
void waves_respect_the_order_of_regions_that_meet(Boundary boundary) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Box<D> box{100.0, boundary};
  std::vector<Region<D>> regions(400);
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const double half_width = k % 37 == 0 ? 30.0 * unit(rng) : 1.0 + 4.0 * unit(rng);
    for (int a = 0; a < D; ++a) {
      const double centre = box.periodic() ? box.length * (2.0 * unit(rng) - 0.5) : box.length * unit(rng);
      regions[k].lo[a] = centre - half_width * (0.5 + unit(rng));
      regions[k].hi[a] = centre + half_width * (0.5 + unit(rng));
    }
  }
  const auto waves = waves_of_regions<D>(regions, box);
  std::vector<int> wave_of(regions.size(), -1);
  for (std::size_t w = 0; w < waves.size(); ++w) {
    EXPECT_FALSE(waves[w].empty());
    EXPECT_TRUE(std::is_sorted(waves[w].begin(), waves[w].end()));
    for (std::size_t k : waves[w]) {
      ASSERT_EQ(wave_of[k], -1) << "region " << k << " twice";
      wave_of[k] = static_cast<int>(w);
    }
  }
  int met = 0;
  for (std::size_t j = 0; j < regions.size(); ++j) {
    ASSERT_GE(wave_of[j], 0) << "region " << j << " in no wave";
    for (std::size_t i = 0; i < j; ++i)
      if (regions_meet(regions[i], regions[j], box)) {
        ++met;
        EXPECT_LT(wave_of[i], wave_of[j]) << "regions " << i << " and " << j << " meet";
      }
  }
  EXPECT_GT(met, 100);                         // the test has conflicts to respect
  EXPECT_LT(waves.size(), regions.size() / 4);  // and the waves are not one region each
}

TEST(RepairWaves, RegionsThatMeetAreInWavesInTheirOrder) {
  waves_respect_the_order_of_regions_that_meet<2>(Boundary::walls);
  waves_respect_the_order_of_regions_that_meet<2>(Boundary::periodic);
  waves_respect_the_order_of_regions_that_meet<3>(Boundary::walls);
  waves_respect_the_order_of_regions_that_meet<3>(Boundary::periodic);
}


TEST(AdhesiveSet, GroupsAreTheConnectedBodiesInOrderOfTheirLowestId) {
  AdhesiveSet S(10);
  S.add(0, 1, 5, 7);
  S.add(2, 3, 2, 9);
  S.add(4, 5, 7, 9);  // joins {5, 7} and {2, 9}
  S.add(6, 7, 1, 3);
  EXPECT_FALSE(S.add(5, 4, 9, 7));  // the same pair again
  const std::vector<CollisionGroup> g = S.take_changed_groups();
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[0].bodies, (std::vector<std::int32_t>{1, 3}));
  EXPECT_EQ(g[1].bodies, (std::vector<std::int32_t>{2, 5, 7, 9}));
  EXPECT_EQ(g[1].pairs, (std::vector<std::int32_t>{0, 1, 2}));
  EXPECT_TRUE(S.take_changed_groups().empty());  // nothing changed since
  S.add(8, 9, 3, 4);
  const std::vector<CollisionGroup> again = S.take_changed_groups();
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].bodies, (std::vector<std::int32_t>{1, 3, 4}));
  S.clear();
  EXPECT_TRUE(S.empty());
  EXPECT_FALSE(S.contains(0, 1));
  S.add(0, 1, 5, 6);  // bodies start afresh after clear
  EXPECT_EQ(S.take_changed_groups()[0].bodies, (std::vector<std::int32_t>{5, 6}));
}

// With kParallelLoopMin groups or more, the groups are copied and sorted on the threads,
// then put in order: the same groups in the same order as on one thread, lowest body first,
// whatever order their pairs were added in.
TEST(AdhesiveSet, ManyGroupsComeInOrderOfTheirLowestIdOnAnyNumberOfThreads) {
  const int n_groups = static_cast<int>(2 * kParallelLoopMin);
  auto groups_on = [&](int threads) {
    const int previous = omp_get_max_threads();
    omp_set_num_threads(threads);
    AdhesiveSet S(3 * n_groups);
    // Group g joins bodies g, 3 n - 1 - g and n + g by two pairs; groups added last first.
    for (int g = n_groups - 1; g >= 0; --g) {
      S.add(4 * g, 4 * g + 1, 3 * n_groups - 1 - g, n_groups + g);
      S.add(4 * g + 2, 4 * g + 3, n_groups + g, g);
    }
    std::vector<CollisionGroup> groups = S.take_changed_groups();
    omp_set_num_threads(previous);
    return groups;
  };
  const std::vector<CollisionGroup> one = groups_on(1), two = groups_on(2);
  ASSERT_EQ(one.size(), static_cast<std::size_t>(n_groups));
  ASSERT_EQ(two.size(), one.size());
  for (int g = 0; g < n_groups; ++g) {
    EXPECT_EQ(one[g].bodies, (std::vector<std::int32_t>{g, n_groups + g, 3 * n_groups - 1 - g}));
    const std::int32_t first_pair = 2 * (n_groups - 1 - g);  // S numbers pairs as they come
    EXPECT_EQ(one[g].pairs, (std::vector<std::int32_t>{first_pair, first_pair + 1}));
    EXPECT_EQ(two[g].bodies, one[g].bodies);
    EXPECT_EQ(two[g].pairs, one[g].pairs);
  }
}

// add_all is the adds one by one (its prefetches change nothing): the same pairs in the
// same order, repeats dropped, the same groups. Enough pairs that the prefetches reach
// ahead into the list, and a table that grows while it is filled.
TEST(AdhesiveSet, AddingAListIsAddingItsPairsOneByOne) {
  const int n_spheres = 3000, n_clusters = 700;
  std::mt19937 rng(11);
  std::vector<std::int32_t> cluster_of(n_spheres);
  for (auto& c : cluster_of) c = static_cast<std::int32_t>(rng() % n_clusters);
  std::vector<SpherePair> pairs;
  for (int k = 0; k < 4000; ++k) {
    const int i = static_cast<int>(rng() % n_spheres), j = static_cast<int>(rng() % n_spheres);
    if (i != j) pairs.push_back({std::min(i, j), std::max(i, j), 0.0});
  }
  for (int k = 0; k < 100; ++k) pairs.push_back(pairs[rng() % pairs.size()]);  // repeats
  AdhesiveSet one_by_one(n_clusters), listed(n_clusters);
  for (const SpherePair& p : pairs) one_by_one.add(p.i, p.j, cluster_of[p.i], cluster_of[p.j]);
  listed.add_all(pairs, cluster_of);
  ASSERT_EQ(listed.pairs().size(), one_by_one.pairs().size());
  for (std::size_t k = 0; k < listed.pairs().size(); ++k) {
    EXPECT_EQ(listed.pairs()[k].i, one_by_one.pairs()[k].i);
    EXPECT_EQ(listed.pairs()[k].j, one_by_one.pairs()[k].j);
  }
  const std::vector<CollisionGroup> a = one_by_one.take_changed_groups(), b = listed.take_changed_groups();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t g = 0; g < a.size(); ++g) {
    EXPECT_EQ(a[g].bodies, b[g].bodies);
    EXPECT_EQ(a[g].pairs, b[g].pairs);
  }
}

// The marks of one group answer for its spheres alone: those of an earlier group (left in
// the thread's array) are not read as this one's, and cluster ids beyond any earlier
// group's grow the array.
TEST(GroupMarks, GiveTheBodyOfEachSphereOfTheGroupAndNothingForTheOthers) {
  const std::vector<std::int32_t> cluster_of_sphere{0, 0, 1, 2, 2, 3, 5};
  {
    const GroupMarks marks(cluster_of_sphere, 4, {{1, 0}, {3, 1}});
    const std::vector<int> expected{-1, -1, 0, -1, -1, 1};
    for (int i = 0; i < 6; ++i) EXPECT_EQ(marks.body_index(i), expected[i]) << "sphere " << i;
  }
  {
    const GroupMarks marks(cluster_of_sphere, 6, {{0, 0}, {2, 0}, {5, 3}});
    const std::vector<int> expected{0, 0, -1, 0, 0, -1, 3};
    for (int i = 0; i < 7; ++i) EXPECT_EQ(marks.body_index(i), expected[i]) << "sphere " << i;
  }
}

// One thread, one group at a time: a second set of marks would overwrite the first's.
TEST(GroupMarks, AThreadCannotHoldTwoAtOnce) {
  const std::vector<std::int32_t> cluster_of_sphere{0, 1};
  const GroupMarks first(cluster_of_sphere, 2, {{0, 0}});
  EXPECT_THROW(GroupMarks(cluster_of_sphere, 2, {{1, 0}}), std::logic_error);
  EXPECT_EQ(first.body_index(0), 0);
  EXPECT_EQ(first.body_index(1), -1);
}

TEST(StepBodies, LinksJoinBodiesAndDissolvingGivesTheLinksBack) {
  StepBodies bodies(8);
  EXPECT_EQ(bodies.body_of(3), 3);
  EXPECT_EQ(bodies.clusters_of(3), (std::vector<std::int32_t>{3}));
  bodies.link({10, 20, 0.5}, 1, 2);
  bodies.link({30, 40, 0.5}, 2, 5);
  bodies.link({50, 60, 0.5}, 6, 7);
  EXPECT_EQ(bodies.body_of(1), bodies.body_of(5));
  EXPECT_NE(bodies.body_of(1), bodies.body_of(6));
  std::vector<std::int32_t> clusters = bodies.clusters_of(bodies.body_of(5));
  std::sort(clusters.begin(), clusters.end());
  EXPECT_EQ(clusters, (std::vector<std::int32_t>{1, 2, 5}));
  EXPECT_EQ(bodies.all_links().size(), 3u);
  const std::vector<SpherePair> links = bodies.dissolve(bodies.body_of(2));
  EXPECT_EQ(links.size(), 2u);
  for (int c : {1, 2, 5}) {
    EXPECT_EQ(bodies.body_of(c), c);
    EXPECT_TRUE(bodies.links_of(c).empty());
  }
  EXPECT_EQ(bodies.all_links().size(), 1u);
  bodies.clear();
  EXPECT_EQ(bodies.body_of(7), 7);
  EXPECT_TRUE(bodies.all_links().empty());
}

// Two unit spheres (scaled contact distance 1) overlapping by `overlap`, free to move.
DahaProblem<2> overlapping_pair(double overlap) {
  DahaProblem<2> p;
  p.inverse_mass = {1.0, 1.0};
  p.n_spheres = 2;
  DahaPair<2> q;
  q.a = 0;
  q.b = 1;
  q.base = Vec<2>(1.0 - overlap, 0.0);
  q.sigma = 1.0;
  p.pairs.push_back(q);
  return p;
}

TEST(Daha, OverlappingPairEndsTouchingWithTheEquilibriumMultiplier) {
  DahaProblem<2> p = overlapping_pair(0.4);
  DahaParameters params;
  std::vector<Vec<2>> u;
  const DahaResult r = minimise(p, params, u);
  ASSERT_TRUE(r.converged);
  const double d = (p.pairs[0].base + u[0] - u[1]).norm();
  EXPECT_NEAR(d, 1.0, params.eps_c);
  EXPECT_NEAR(p.pairs[0].lambda, 0.5, 0.05);  // (3.25): grad W = d balances lambda grad phi = -2 lambda d
  EXPECT_NEAR((u[0] + u[1]).norm(), 0.0, 1e-12);  // equal masses: the centre stays
}

// A sphere 10 times lighter than the mean sphere overlapping one 25 times heavier (a mass
// ratio of 250), under each model's parameters: the minimisation converges to touching
// spheres, the heavy one moving 250 times less, so that their centre of mass stays put.
// (Mass-weighted steps taken with the mean sphere as unit gave the light sphere 10 times
// the stable gain, and its velocity grew without bound.)
TEST(Daha, LightSphereAgainstAHeavyOneConvergesAndKeepsTheCentreOfMass) {
  for (TsModel model : {TsModel::rigid, TsModel::non_rigid}) {
    DahaProblem<2> p = overlapping_pair(0.4);
    p.inverse_mass = {10.0, 0.04};
    const DahaParameters params = default_daha(model);
    std::vector<Vec<2>> u;
    const DahaResult r = minimise(p, params, u);
    ASSERT_TRUE(r.converged) << to_string(model);
    EXPECT_LT(r.iterations, 500) << to_string(model);
    EXPECT_NEAR((p.pairs[0].base + u[0] - u[1]).norm(), 1.0, params.eps_c) << to_string(model);
    EXPECT_NEAR((u[0] / 10.0 + u[1] / 0.04).norm(), 0.0, 1e-9) << to_string(model);  // sum of m u
  }
}

// An iteration that diverges (a step far beyond the stable one) must not pass the stopping
// test: std::max skips a NaN, and a NaN iterate looked like one that no longer moved.
TEST(Daha, ADivergingMinimisationIsNotConverged) {
  DahaProblem<2> p = overlapping_pair(0.4);
  DahaParameters params;
  params.delta = 200.0;
  params.stall_iterations = 0;
  std::vector<Vec<2>> u;
  const DahaResult r = minimise(p, params, u);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations, params.max_iterations);
}

TEST(Daha, StallDetectionGivesUpOnAProblemWithoutSolution) {
  // A sphere between two fixed spheres 1.5 apart: it cannot be 1 away from both.
  DahaProblem<2> p;
  p.inverse_mass = {1.0, 0.0};
  p.n_spheres = 3;
  for (double x : {-0.75, 0.75}) {
    DahaPair<2> q;
    q.a = 0;
    q.b = 1;
    q.base = Vec<2>(x, 0.0);
    q.sigma = 1.0;
    p.pairs.push_back(q);
  }
  DahaParameters params;
  params.max_iterations = 20000;
  params.stall_iterations = 0;
  std::vector<Vec<2>> u;
  DahaProblem<2> copy = p;
  EXPECT_EQ(minimise(copy, params, u).iterations, 20000);
  params.stall_iterations = 200;
  const DahaResult r = minimise(p, params, u);
  EXPECT_FALSE(r.converged);
  EXPECT_LT(r.iterations, 5000);
}

TEST(Daha, BondDoesNotStretchBeyondItsLimit) {
  // Sphere 0 overlaps sphere 1 deeply; sphere 1 is bonded to sphere 2 (limit 1.1), which
  // is fixed. Without the bond the push would drive 1 away from 2; with it, the bond ends
  // within its limit and the overlap is resolved by moving sphere 0.
  DahaProblem<2> p;
  p.inverse_mass = {1.0, 1.0, 0.0};
  p.n_spheres = 3;
  DahaPair<2> hit;
  hit.a = 0;
  hit.b = 1;
  hit.base = Vec<2>(-0.5, 0.0);
  hit.sigma = 1.0;
  DahaPair<2> bond;
  bond.a = 1;
  bond.b = 2;
  bond.base = Vec<2>(-1.0, 0.0);
  bond.sigma = 1.0;
  bond.stretch_limit = 1.1;
  p.pairs = {hit, bond};
  DahaParameters params;
  std::vector<Vec<2>> u;
  ASSERT_TRUE(minimise(p, params, u).converged);
  EXPECT_GE((hit.base + u[0] - u[1]).norm(), 1.0 - params.eps_c);
  const double stretch = (bond.base + u[1] - u[2]).norm();
  EXPECT_LE(stretch, 1.1 * (1.0 + params.eps_c));
  EXPECT_GE(stretch, 1.0 - params.eps_c);
}

}  // namespace
}  // namespace ballagg
