// The shared state: lazy positions, merging of clusters (rule 2.9), wall pinning.
#include <gtest/gtest.h>

#include "ballagg/core/state_codec.hpp"
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

// Extents are stored only for clusters of several spheres; a single sphere's is computed.
// Whatever the history, every cluster's extent is the box of its spheres as they are.
template <int D>
void expect_extents_match_the_spheres(const State<D>& s) {
  for (int c = 0; c < static_cast<int>(s.clusters.size()); ++c) {
    if (!s.clusters[c].alive()) continue;
    Vec<D> lo = Vec<D>::Constant(1e300), hi = Vec<D>::Constant(-1e300);
    for (int i : s.clusters[c].members) {
      lo = lo.cwiseMin(s.spheres.offset[i] - Vec<D>::Constant(s.spheres.radius[i]));
      hi = hi.cwiseMax(s.spheres.offset[i] + Vec<D>::Constant(s.spheres.radius[i]));
    }
    EXPECT_NEAR((s.extent(c).lo - lo).norm(), 0.0, 1e-13) << "cluster " << c;
    EXPECT_NEAR((s.extent(c).hi - hi).norm(), 0.0, 1e-13) << "cluster " << c;
  }
}

TEST(State, ExtentsFollowMergesSplitsAndCheckpoints) {
  State<2> s = make_state<2>(20, Boundary::walls,
                             {{vec<2>(5, 5), vec<2>(1, 0), 0.5}, {vec<2>(6, 5), vec<2>(0, 0), 0.5},
                              {vec<2>(6.8, 5.1), vec<2>(0, 1), 0.3}, {vec<2>(10, 10), vec<2>(0, 0), 0.4},
                              {vec<2>(10.8, 10), vec<2>(0, 0), 0.4}});
  expect_extents_match_the_spheres(s);
  const int lone = s.spheres.cluster[3];
  EXPECT_NEAR((s.extent(lone).hi - s.extent(lone).lo - vec<2>(0.8, 0.8)).norm(), 0.0, 1e-14);  // its own box
  const int a = s.merge(0, 1, 0.0);
  const int b = s.merge(3, 4, 0.0);
  const int c = s.merge(1, 2, 0.0);  // a pair absorbs a third sphere
  expect_extents_match_the_spheres(s);
  EXPECT_EQ(c, a);
  // The checkpoint keeps them: stored ones as they were, single spheres' from the spheres.
  const State<2> restored = StateCodec<2>::decode(StateCodec<2>::encode(s));
  EXPECT_EQ(StateCodec<2>::encode(restored), StateCodec<2>::encode(s));
  expect_extents_match_the_spheres(restored);
  // Splitting the pair into single spheres frees its stored extent for the next merge.
  std::vector<std::int32_t> empty;
  for (int k = 0; k < static_cast<int>(s.clusters.size()); ++k)
    if (!s.clusters[k].alive()) empty.push_back(k);
  const std::vector<std::int32_t> pieces = s.split_rigid(b, empty, 0.0);
  ASSERT_EQ(pieces.size(), 2u);
  expect_extents_match_the_spheres(s);
  s.merge(s.clusters[pieces[0]].members.front(), s.clusters[pieces[1]].members.front(), 0.0);
  expect_extents_match_the_spheres(s);
}

// Collision times (the TC model's memory) are kept only once asked for, and then through
// merges and checkpoints.
TEST(State, CollisionTimesAreKeptOnlyWhenAskedFor) {
  const std::vector<Ball<2>> balls{{vec<2>(5, 5), vec<2>(1, 0)}, {vec<2>(6, 5), vec<2>(0, 0)},
                                   {vec<2>(7, 5), vec<2>(0, 0)}};
  State<2> s = make_state<2>(20, Boundary::walls, balls);
  s.set_last_collision_time(0, 1.0);
  const int pair = s.merge(0, 1, 2.0);
  EXPECT_EQ(s.last_collision_time(pair), State<2>::kNeverCollided);
  EXPECT_EQ(StateCodec<2>::decode(StateCodec<2>::encode(s)).last_collision_time(pair), State<2>::kNeverCollided);

  State<2> kept = make_state<2>(20, Boundary::walls, balls);
  kept.keep_collision_times();
  const int lone = kept.spheres.cluster[2];
  EXPECT_EQ(kept.last_collision_time(lone), State<2>::kNeverCollided);
  kept.set_last_collision_time(lone, 1.0);
  const int merged = kept.merge(0, 1, 2.0);
  EXPECT_EQ(kept.last_collision_time(merged), 2.0);
  const State<2> restored = StateCodec<2>::decode(StateCodec<2>::encode(kept));
  EXPECT_EQ(restored.last_collision_time(merged), 2.0);
  EXPECT_EQ(restored.last_collision_time(lone), 1.0);
  EXPECT_EQ(StateCodec<2>::encode(restored), StateCodec<2>::encode(kept));
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
