// The pool of short lists behind the event calendar and the neighbour lists: each owner's
// values survive growth, shrinking and the other owners' changes; freed blocks are reused
// (also when the last owner leaves); appending one owner's list to another's and swapping
// two owners' lists keep every value in order; binary-heap operations
// on a pooled list give the same arrangement as on a std::vector; sizes beyond the limit
// are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <functional>
#include <stdexcept>
#include <vector>

#include "ballagg/core/pooled_lists.hpp"
#include "ballagg/core/random.hpp"

namespace ballagg {
namespace {

template <class Pool>
std::vector<int> values(const Pool& pool, int o) {
  return {pool.begin(o), pool.end(o)};
}

TEST(PooledLists, StartsEmptyWithoutBlocks) {
  PooledLists<int> pool;
  pool.reset(3);
  EXPECT_EQ(pool.owners(), 3);
  for (int o = 0; o < 3; ++o) {
    EXPECT_TRUE(pool.empty(o));
    EXPECT_EQ(pool.capacity(o), 0u);
    EXPECT_EQ(pool.begin(o), pool.end(o));
  }
}

TEST(PooledLists, GrowsByDoublingAndKeepsValues) {
  PooledLists<int, 3> pool;  // chunks of 8: lists of 16 and more get blocks of their own
  pool.reset(2);
  pool.push_back(1, -7);
  for (int k = 0; k < 40; ++k) {
    pool.push_back(0, k);
    EXPECT_EQ(pool.capacity(0), std::bit_ceil(static_cast<unsigned>(k + 1)));
  }
  std::vector<int> expected(40);
  for (int k = 0; k < 40; ++k) expected[k] = k;
  EXPECT_EQ(values(pool, 0), expected);
  EXPECT_EQ(values(pool, 1), std::vector<int>{-7});
}

TEST(PooledLists, OtherOwnersDoNotMoveWhenOneGrows) {
  PooledLists<int, 2> pool;
  pool.reset(3);
  pool.push_back(0, 1);
  pool.push_back(2, 2);
  const int* first = pool.data(0);
  const int* last = pool.data(2);
  for (int k = 0; k < 100; ++k) pool.push_back(1, k);  // many new chunks and a big block
  EXPECT_EQ(pool.data(0), first);
  EXPECT_EQ(pool.data(2), last);
  EXPECT_EQ(*first, 1);
  EXPECT_EQ(*last, 2);
}

TEST(PooledLists, ReusesAFreedBlockOfTheSameClass) {
  PooledLists<int> pool;
  pool.reset(3);
  for (int k = 0; k < 3; ++k) pool.push_back(0, k);  // a block of 4
  const int* freed = pool.data(0);
  pool.release(0);
  EXPECT_TRUE(pool.empty(0));
  EXPECT_EQ(pool.capacity(0), 0u);
  pool.push_back(1, 5);  // a block of 1: not the freed one
  EXPECT_NE(pool.data(1), freed);
  const std::vector<int> four{1, 2, 3, 4};
  pool.assign(2, four.data(), four.size());
  EXPECT_EQ(pool.data(2), freed);
  EXPECT_EQ(values(pool, 2), four);
  EXPECT_EQ(values(pool, 1), std::vector<int>{5});
}

// The last owner leaves for good (a sphere coagulated away): its block is free again, the
// others keep theirs.
TEST(PooledLists, PoppingTheLastOwnerFreesItsBlock) {
  PooledLists<int> pool;
  pool.reset(3);
  for (int k = 0; k < 4; ++k) pool.push_back(2, k);  // a block of 4
  pool.push_back(0, 7);
  const int* freed = pool.data(2);
  pool.pop_owner();
  EXPECT_EQ(pool.owners(), 2);
  EXPECT_EQ(values(pool, 0), std::vector<int>{7});
  const std::vector<int> four{1, 2, 3, 4};
  pool.assign(1, four.data(), four.size());
  EXPECT_EQ(pool.data(1), freed);
}

TEST(PooledLists, AssignKeepsAFittingBlockAndShrinksAnOversizedOne) {
  PooledLists<int> pool;
  pool.reset(1);
  std::vector<int> many(64, 3);
  pool.assign(0, many.data(), many.size());
  EXPECT_EQ(pool.capacity(0), 64u);
  const std::vector<int> some(20, 4);  // least block 32: within the slack
  pool.assign(0, some.data(), some.size());
  EXPECT_EQ(pool.capacity(0), 64u);
  EXPECT_EQ(values(pool, 0), some);
  const std::vector<int> few{8, 9};  // least block 2: 64 is oversized
  pool.assign(0, few.data(), few.size());
  EXPECT_EQ(pool.capacity(0), 2u);
  EXPECT_EQ(values(pool, 0), few);
  pool.assign(0, few.data(), 0);
  EXPECT_TRUE(pool.empty(0));
  EXPECT_EQ(pool.capacity(0), 2u);  // an empty list keeps a small block
}

TEST(PooledLists, RandomOperationsMatchVectors) {
  PooledLists<int, 4> pool;
  std::vector<std::vector<int>> ref(50);
  pool.reset(50);
  Random rng(7, RandomPurpose::positions);
  for (int step = 0; step < 20000; ++step) {
    const int o = static_cast<int>(rng.uniform(0.0, 50.0));
    const double what = rng.uniform();
    if (what < 0.5) {
      const int x = static_cast<int>(rng.uniform(-1e6, 1e6));
      pool.push_back(o, x);
      ref[o].push_back(x);
    } else if (what < 0.75) {
      if (!ref[o].empty()) {
        pool.pop_back(o);
        ref[o].pop_back();
      }
    } else if (what < 0.95) {
      std::vector<int> v(static_cast<std::size_t>(rng.uniform(0.0, 40.0)), step);
      pool.assign(o, v.data(), v.size());
      ref[o] = v;
    } else {
      pool.release(o);
      ref[o].clear();
    }
    ASSERT_EQ(values(pool, o), ref[o]) << "step " << step;
  }
  for (int o = 0; o < 50; ++o) EXPECT_EQ(values(pool, o), ref[o]);
}

TEST(PooledLists, AppendingAndSwappingOwnersMatchVectors) {
  PooledLists<int, 3> pool;  // chunks of 8: long lists take blocks of their own
  std::vector<std::vector<int>> ref(20);
  pool.reset(20);
  Random rng(5, RandomPurpose::positions);
  for (int step = 0; step < 5000; ++step) {
    const int a = static_cast<int>(rng.uniform(0.0, 20.0));
    const int b = static_cast<int>(rng.uniform(0.0, 20.0));
    const double what = rng.uniform();
    if (what < 0.5) {
      const int x = step;
      pool.push_back(a, x);
      ref[a].push_back(x);
    } else if (what < 0.7 && a != b) {
      pool.append_owner(a, b);
      ref[a].insert(ref[a].end(), ref[b].begin(), ref[b].end());
      ref[b].clear();
      ASSERT_EQ(pool.capacity(b), 0u) << "the appended owner's block goes back to the pool";
    } else if (what < 0.9) {
      pool.swap_owners(a, b);
      std::swap(ref[a], ref[b]);
    } else {
      pool.release(a);
      ref[a].clear();
    }
    ASSERT_EQ(values(pool, a), ref[a]) << "step " << step;
    ASSERT_EQ(values(pool, b), ref[b]) << "step " << step;
  }
  for (int o = 0; o < 20; ++o) EXPECT_EQ(values(pool, o), ref[o]);
}

TEST(PooledLists, HeapOperationsGiveTheVectorsArrangement) {
  PooledLists<int, 2> pool;
  pool.reset(2);
  std::vector<int> ref;
  Random rng(11, RandomPurpose::positions);
  for (int step = 0; step < 2000; ++step) {
    if (ref.empty() || rng.uniform() < 0.6) {
      const int x = static_cast<int>(rng.uniform(0.0, 100.0));  // with ties
      pool.push_back(0, x);
      std::push_heap(pool.begin(0), pool.end(0), std::greater<>());
      ref.push_back(x);
      std::push_heap(ref.begin(), ref.end(), std::greater<>());
      pool.push_back(1, x);  // the other owner grows in between
    } else {
      EXPECT_EQ(pool.front(0), ref.front());
      std::pop_heap(pool.begin(0), pool.end(0), std::greater<>());
      pool.pop_back(0);
      std::pop_heap(ref.begin(), ref.end(), std::greater<>());
      ref.pop_back();
    }
    ASSERT_EQ(values(pool, 0), ref);
  }
}

TEST(PooledLists, RefusesAListBeyondItsLimit) {
  PooledLists<int> pool;
  pool.reset(1);
  const int one = 1;
  EXPECT_THROW(pool.assign(0, &one, std::size_t{PooledLists<int>::kMaxSize} + 1), std::length_error);
  EXPECT_TRUE(pool.empty(0));
}

TEST(PooledLists, ResetReleasesEverything) {
  PooledLists<int, 2> pool;
  pool.reset(2);
  for (int k = 0; k < 30; ++k) pool.push_back(0, k);
  pool.reset(4);
  EXPECT_EQ(pool.owners(), 4);
  for (int o = 0; o < 4; ++o) EXPECT_EQ(pool.capacity(o), 0u);
  pool.push_back(3, 9);
  EXPECT_EQ(values(pool, 3), std::vector<int>{9});
}

}  // namespace
}  // namespace ballagg
