// The shared state: lazy positions, merging of clusters (rule 2.9), wall pinning.
#include <gtest/gtest.h>

#include "support.hpp"

namespace ballagg {
namespace {
using testing::Ball;
using testing::make_state;
using testing::vec;

TEST(State, PositionsFollowStraightLinesFromTheAnchor) {
  State<2> s = make_state<2>(20, Boundary::walls, {{vec<2>(5, 5), vec<2>(1, -0.5)}});
  EXPECT_EQ(s.position(0, 2.0), vec<2>(7, 4));
}

TEST(State, PeriodicPositionsAreFoldedIntoTheBox) {
  State<2> s = make_state<2>(10, Boundary::periodic, {{vec<2>(9, 5), vec<2>(1, 0)}});
  EXPECT_NEAR(s.position(0, 3.0)[0], 2.0, 1e-14);
}

TEST(State, MergeKeepsTheLargerClusterAndAveragesVelocityByMass) {
  State<2> s = make_state<2>(20, Boundary::walls,
                             {{vec<2>(5, 5), vec<2>(1, 0), 0.5, 1.0, 7},
                              {vec<2>(6, 5), vec<2>(1, 0), 0.5, 1.0, 7},
                              {vec<2>(7, 5), vec<2>(-2, 1), 0.5, 2.0}});
  ASSERT_EQ(s.n_clusters(), 2);
  const int keep = s.merge(1, 2, 0.0);
  EXPECT_EQ(keep, s.spheres.cluster[0]);
  EXPECT_EQ(s.n_clusters(), 1);
  EXPECT_EQ(s.largest_cluster(), 3);
  const Cluster<2>& k = s.clusters[keep];
  EXPECT_DOUBLE_EQ(k.mass, 4.0);
  EXPECT_NEAR((k.velocity - vec<2>(-0.5, 0.5)).norm(), 0.0, 1e-15);
  // The absorbed sphere keeps its place; the cluster's box covers all three spheres.
  EXPECT_NEAR((s.position(2, 0.0) - vec<2>(7, 5)).norm(), 0.0, 1e-14);
  EXPECT_NEAR(s.extent(keep).hi[0] - s.extent(keep).lo[0], 3.0, 1e-14);
  EXPECT_NEAR(s.extent(keep).hi[1] - s.extent(keep).lo[1], 1.0, 1e-14);
}

TEST(State, MergeAcrossAPeriodicFaceJoinsTheNearestImages) {
  // Spheres touch through the face x = 0: the merged cluster is 2 diameters wide, not L.
  State<2> s = make_state<2>(10, Boundary::periodic,
                             {{vec<2>(0.4, 5), vec<2>(0, 1)}, {vec<2>(9.4, 5), vec<2>(0, -1)}});
  const int keep = s.merge(0, 1, 0.0);
  const Cluster<2>& k = s.clusters[keep];
  EXPECT_NEAR(s.extent(keep).hi[0] - s.extent(keep).lo[0], 2.0, 1e-14);
  EXPECT_NEAR((s.unwrapped_position(0, 0) - s.unwrapped_position(1, 0)).norm(), 1.0, 1e-14);
  EXPECT_EQ(k.velocity, vec<2>(0, 0));
}

TEST(State, ClusterSpanningTheBoxBetweenWallsIsPinnedAlongThatAxis) {
  // A rod of 4 unit discs in a box of length 4 touches both walls: it cannot move along x.
  std::vector<Ball<2>> rod;
  for (int k = 0; k < 4; ++k) rod.push_back({vec<2>(0.5 + k, 2), vec<2>(0.3, 0.2), 0.5, 1.0, 1});
  State<2> s = make_state<2>(4, Boundary::walls, rod);
  EXPECT_TRUE(s.pinned(0, 0));
  EXPECT_FALSE(s.pinned(0, 1));
  EXPECT_EQ(s.clusters[0].velocity, vec<2>(0, 0.2));
}

TEST(State, TotalsSumOverClusters) {
  State<3> s = make_state<3>(10, Boundary::walls,
                             {{vec<3>(2, 2, 2), vec<3>(1, 0, 0), 0.5, 2.0}, {vec<3>(5, 5, 5), vec<3>(0, 0, -3), 0.5, 1.0}});
  EXPECT_DOUBLE_EQ(s.kinetic_energy(), 0.5 * 2 * 1 + 0.5 * 1 * 9);
  EXPECT_EQ(s.momentum(), vec<3>(2, 0, -3));
  EXPECT_DOUBLE_EQ(s.total_mass(), 3.0);
}

}  // namespace
}  // namespace ballagg

namespace ballagg {
namespace {

TEST(Box, RoundingHelpersMatchTheLibrary) {
  for (double x : {0.0, 0.49999999999999994, 0.5, 1.5, 2.5, -0.5, -1.5, -2.4999, 3.7, -3.7, 1e6 + 0.5, -1e-300, 123456.499}) {
    EXPECT_EQ(round_to_integer(x), std::nearbyint(x)) << x;
    EXPECT_EQ(floor_to_integer(x), std::floor(x)) << x;
  }
}

TEST(Box, PeriodicFoldAndMinimumImage) {
  const Box<2> box{10.0, Boundary::periodic};
  EXPECT_DOUBLE_EQ(box.wrap(-0.25), 9.75);
  EXPECT_DOUBLE_EQ(box.wrap(23.5), 3.5);
  EXPECT_EQ(box.wrap(-1e-17), 0.0);  // would round to exactly L
  const Vec<2> d = box.separation(Vec<2>(0.5, 9.0), Vec<2>(9.5, 1.0));
  EXPECT_DOUBLE_EQ(d[0], 1.0);
  EXPECT_DOUBLE_EQ(d[1], -2.0);
}

}  // namespace
}  // namespace ballagg
