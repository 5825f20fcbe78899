// The parts of the time-stepping engine on their own: the pair index, the adhesive set and
// its groups, the bodies of a step, and the minimiser's stopping rules and bonds.
#include <cmath>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "ballagg/core/pair_index.hpp"
#include "ballagg/engines/time_stepping/adhesive_set.hpp"
#include "ballagg/engines/time_stepping/daha.hpp"
#include "ballagg/engines/time_stepping/step_bodies.hpp"

namespace ballagg {
namespace {

TEST(PairIndex, FindsEveryPairInEitherOrderAndForgetsThemWhenCleared) {
  PairIndex index;
  std::mt19937 rng(3);
  std::set<std::pair<int, int>> stored;
  for (int k = 0; k < 5000; ++k) {  // past several growths of the table
    int i = static_cast<int>(rng() % 2000), j = static_cast<int>(rng() % 2000);
    if (i == j) continue;
    const auto [value, added] = index.insert(i, j, k);
    EXPECT_EQ(added, stored.insert({std::min(i, j), std::max(i, j)}).second);
    if (!added) EXPECT_NE(value, k);
  }
  EXPECT_EQ(index.size(), stored.size());
  for (const auto& [i, j] : stored) {
    EXPECT_NE(index.find(i, j), PairIndex::kAbsent);
    EXPECT_EQ(index.find(i, j), index.find(j, i));
  }
  EXPECT_EQ(index.find(2001, 2002), PairIndex::kAbsent);
  index.clear();
  EXPECT_EQ(index.size(), 0u);
  for (const auto& [i, j] : stored) EXPECT_EQ(index.find(i, j), PairIndex::kAbsent);
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
