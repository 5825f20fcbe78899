// The pair index of core/pair_index.hpp: a hash table of sphere pairs that finds them in
// either order, forgets them when cleared, and keeps its storage within bounds.
#include <random>
#include <set>
#include <utility>

#include <gtest/gtest.h>

#include "ballagg/core/pair_index.hpp"

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
    if (!added) {
      EXPECT_NE(value, k);
    }
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

// A table grown for a large set is shrunk when it is cleared with few entries, and one
// whose entries fill a fair part of it is kept; either way it works on after clear().
TEST(PairIndex, ShrinksATableFarLargerThanItsEntriesWhenCleared) {
  PairIndex index;
  for (int k = 0; k < 100000; ++k) index.insert(k, k + 1, k);
  const std::size_t large = index.capacity();
  EXPECT_GE(large, 200000u);
  index.clear();  // 100 000 entries of 262 144 slots: kept
  EXPECT_EQ(index.capacity(), large);
  for (int k = 0; k < 10; ++k) index.insert(k, k + 2, k);
  index.clear();  // 10 entries: shrunk
  EXPECT_LT(index.capacity(), large);
  for (int k = 0; k < 3000; ++k) EXPECT_TRUE(index.insert(k, k + 3, k).second);
  for (int k = 0; k < 3000; ++k) {
    EXPECT_EQ(index.find(k + 3, k), k);
    EXPECT_EQ(index.find(k, k + 1), PairIndex::kAbsent);
  }
  EXPECT_EQ(index.size(), 3000u);
}

// Large, small, large again (the early steps of a large run): a table shrunk at clear()
// hashes into the front of the storage it keeps, and grows back within it, finding every
// pair it holds at each size and none of those cleared.
TEST(PairIndex, ShrinksAndGrowsBackWithinTheStorageItKeeps) {
  PairIndex index;
  for (int round = 0; round < 3; ++round) {
    index.reserve(50000);
    for (int k = 0; k < 50000; ++k) EXPECT_TRUE(index.insert(k, k + 1 + round, k).second);
    const std::size_t large = index.capacity();
    EXPECT_GE(large, 100000u);
    for (int k = 0; k < 50000; k += 7) EXPECT_EQ(index.find(k + 1 + round, k), k);
    index.clear();
    for (int k = 0; k < 20; ++k) index.insert(k, k + 50, k);
    index.clear();  // 20 entries: hashed into a small table again
    EXPECT_LT(index.capacity(), large);
    for (int k = 0; k < 2000; ++k) EXPECT_TRUE(index.insert(k, k + 70, -k).second);  // grows by doublings
    for (int k = 0; k < 2000; ++k) {
      EXPECT_EQ(index.find(k + 70, k), -k);
      EXPECT_EQ(index.find(k, k + 1 + round), PairIndex::kAbsent);
      EXPECT_EQ(index.find(k, k + 50), PairIndex::kAbsent);
    }
    index.clear();
  }
}

TEST(PairIndex, ReserveMakesRoomOnceAndKeepsWhatItHolds) {
  PairIndex index;
  for (int k = 0; k < 500; ++k) index.insert(k, k + 1, k);
  index.reserve(100000);
  const std::size_t reserved = index.capacity();
  EXPECT_GE(reserved, 200000u);
  for (int k = 0; k < 500; ++k) EXPECT_EQ(index.find(k + 1, k), k);
  for (int k = 500; k < 100000; ++k) EXPECT_TRUE(index.insert(k, k + 1, k).second);
  EXPECT_EQ(index.capacity(), reserved);  // no growth while filling what was reserved
  EXPECT_EQ(index.size(), 100000u);
  EXPECT_EQ(index.find(99999, 100000), 99999);
}

}  // namespace
}  // namespace ballagg
