// The clusters of a sphere table as an initial state is assembled from them: labels in
// order of first appearance, members in table order, and a table without a cluster column
// as one cluster per sphere.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/initial/cluster_groups.hpp"

namespace ballagg {
namespace {

std::vector<std::int32_t> members_of(const ClusterGroups& g, int c) {
  const auto m = g.members(c);
  return {m.begin(), m.end()};
}

TEST(ClusterGroups, WithoutAClusterColumnEverySphereIsItsOwnCluster) {
  const ClusterGroups g({}, 4);
  ASSERT_EQ(g.size(), 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(g.label(i), i);
    EXPECT_EQ(members_of(g, i), std::vector<std::int32_t>{i});
  }
}

TEST(ClusterGroups, ClustersAreNumberedInOrderOfFirstAppearanceWithMembersInTableOrder) {
  // Arbitrary values, negative and beyond 32 bits among them.
  const std::int64_t big = std::int64_t{1} << 40;
  const ClusterGroups g({7, big, 7, -3, big, 7}, 6);
  ASSERT_EQ(g.size(), 3);
  EXPECT_EQ(g.label(0), 0);
  EXPECT_EQ(g.label(1), 1);
  EXPECT_EQ(g.label(2), 0);
  EXPECT_EQ(g.label(3), 2);
  EXPECT_EQ(g.label(4), 1);
  EXPECT_EQ(g.label(5), 0);
  EXPECT_EQ(members_of(g, 0), (std::vector<std::int32_t>{0, 2, 5}));
  EXPECT_EQ(members_of(g, 1), (std::vector<std::int32_t>{1, 4}));
  EXPECT_EQ(members_of(g, 2), (std::vector<std::int32_t>{3}));
}

TEST(ClusterGroups, OneClusterHoldsEverySphere) {
  const ClusterGroups g({5, 5, 5}, 3);
  ASSERT_EQ(g.size(), 1);
  EXPECT_EQ(members_of(g, 0), (std::vector<std::int32_t>{0, 1, 2}));
}

TEST(ClusterGroups, NoSpheresNoClusters) {
  EXPECT_EQ(ClusterGroups({}, 0).size(), 0);
}

TEST(ClusterGroups, TakingTheLabelsLeavesNoCluster) {
  ClusterGroups glued({9, 4, 9}, 3);
  EXPECT_EQ(std::move(glued).take_labels(), (std::vector<std::int32_t>{0, 1, 0}));
  EXPECT_EQ(glued.size(), 0);
  ClusterGroups single({}, 3);
  EXPECT_EQ(std::move(single).take_labels(), (std::vector<std::int32_t>{0, 1, 2}));
  EXPECT_EQ(single.size(), 0);
}

}  // namespace
}  // namespace ballagg
