// prefetch_entries is called at every entry of a loop over a list of ids with the index
// kPrefetchAhead places on: it must ask for exactly the entries of the id found there, in
// each array, and never read the list past its end (the last kPrefetchAhead entries of a
// loop have nothing ahead).
#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

#include "ballagg/core/prefetch.hpp"

namespace ballagg {
namespace {

// A list of ids that records every index read from it.
struct WatchedIds {
  std::vector<int> ids;
  mutable std::vector<std::size_t> read;
  std::size_t size() const { return ids.size(); }
  int operator[](std::size_t k) const {
    read.push_back(k);
    return ids.at(k);
  }
};

// An array that records every entry whose address is asked for.
struct WatchedArray {
  std::vector<double> values;
  mutable std::vector<int> asked;
  const double& operator[](int i) const {
    asked.push_back(i);
    return values.at(static_cast<std::size_t>(i));
  }
};

TEST(Prefetch, AsksForTheEntriesOfTheIdAheadInEveryArray) {
  const WatchedIds list{{7, 3, 9, 0, 5, 2, 8, 1, 6, 4, 11, 10, 13, 12, 15, 14, 17, 16, 19, 18}, {}};
  const WatchedArray first{std::vector<double>(20, 0.0), {}}, second{std::vector<double>(20, 1.0), {}};
  for (std::size_t k = 0; k < list.size(); ++k) prefetch_entries(list, k + kPrefetchAhead, first, second);
  std::vector<int> expected;
  std::vector<std::size_t> expected_reads;
  for (std::size_t k = kPrefetchAhead; k < list.size(); ++k) {
    expected.push_back(list.ids[k]);
    expected_reads.push_back(k);
  }
  EXPECT_EQ(first.asked, expected);
  EXPECT_EQ(second.asked, expected);
  EXPECT_EQ(list.read, expected_reads);  // nothing past the end, nothing twice
}

TEST(Prefetch, AShortListIsNeverRead) {
  const WatchedIds list{{2, 0, 1}, {}};
  const WatchedArray array{{0.0, 1.0, 2.0}, {}};
  for (std::size_t k = 0; k < list.size(); ++k) prefetch_entries(list, k + kPrefetchAhead, array);
  EXPECT_TRUE(list.read.empty());
  EXPECT_TRUE(array.asked.empty());
}

TEST(Prefetch, ForEachPrefetchedVisitsEveryIdInOrderAndAsksAhead) {
  WatchedIds list{{}, {}};
  for (int id = 0; id < 40; ++id) list.ids.push_back((id * 7) % 40);
  const WatchedArray array{std::vector<double>(40, 0.0), {}};
  std::vector<int> visited;
  for_each_prefetched(list, [&](int id) { visited.push_back(id); }, array);
  EXPECT_EQ(visited, list.ids);
  const std::vector<int> ahead(list.ids.begin() + kPrefetchAhead, list.ids.end());
  EXPECT_EQ(array.asked, ahead);
}

}  // namespace
}  // namespace ballagg
