// core/disjoint_sets.hpp: the union-find the time-stepping engine's step bodies, the
// state-file check and verify share.
#include <gtest/gtest.h>

#include "ballagg/core/disjoint_sets.hpp"

namespace ballagg {
namespace {

TEST(DisjointSets, TheLargerSetKeepsItsRootAndEqualSizesKeepTheLowerId) {
  DisjointSets sets(6);
  EXPECT_EQ(sets.unite_roots(4, 2), 2);  // equal sizes: the lower id
  EXPECT_EQ(sets.unite_roots(5, 2), 2);  // {2, 4} is larger than {5}
  EXPECT_EQ(sets.unite_roots(1, 2), 2);
  EXPECT_EQ(sets.unite(0, 3), 0);
  EXPECT_EQ(sets.unite(3, 4), 2);        // {0, 3} joins the larger {1, 2, 4, 5}
  for (int id = 0; id < 6; ++id) EXPECT_EQ(sets.root(id), 2) << id;
}

TEST(DisjointSets, RootAgreesWithFindAndResetDetachesOneId) {
  DisjointSets sets(5);
  sets.unite(0, 1);
  sets.unite(2, 3);
  sets.unite(1, 3);
  for (int id = 0; id < 4; ++id) EXPECT_EQ(sets.root(id), sets.find(id));
  EXPECT_EQ(sets.root(4), 4);
  const int root = sets.root(0);
  for (int id = 0; id < 4; ++id)
    if (id != root) sets.reset(id);
  for (int id = 0; id < 4; ++id) EXPECT_EQ(sets.root(id), id == root ? root : id);
}

}  // namespace
}  // namespace ballagg
