// A cluster's member list: 8 bytes, a single member held in place, longer lists on the
// heap; random appends, erasures, copies and moves give what a std::vector gives.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "ballagg/core/member_list.hpp"
#include "ballagg/core/random.hpp"

namespace ballagg {
namespace {

std::vector<std::int32_t> values(const MemberList& m) { return {m.begin(), m.end()}; }

TEST(MemberList, FitsInEightBytes) { EXPECT_EQ(sizeof(MemberList), 8u); }

TEST(MemberList, HoldsOneMemberInPlaceAndMoreOnTheHeap) {
  MemberList m;
  EXPECT_TRUE(m.empty());
  EXPECT_EQ(m.size(), 0u);
  EXPECT_EQ(m.begin(), m.end());
  m.push_back(7);
  EXPECT_EQ(m.size(), 1u);
  EXPECT_EQ(m.front(), 7);
  // In place: the member's address lies within the list itself.
  const auto* self = reinterpret_cast<const char*>(&m);
  const auto* at = reinterpret_cast<const char*>(m.data());
  EXPECT_TRUE(at >= self && at < self + sizeof m);
  m.push_back(-3);
  m.push_back(2147483647);
  EXPECT_EQ(values(m), (std::vector<std::int32_t>{7, -3, 2147483647}));
  at = reinterpret_cast<const char*>(m.data());
  EXPECT_FALSE(at >= self && at < self + sizeof m);
  m.clear();
  EXPECT_TRUE(m.empty());
}

TEST(MemberList, TheLargestIdAndZeroAreHeldInPlace) {
  for (std::int32_t id : {0, 1, 2147483647}) {
    MemberList m;
    m.push_back(id);
    EXPECT_FALSE(m.empty());
    EXPECT_EQ(values(m), std::vector<std::int32_t>{id});
  }
}

TEST(MemberList, ErasingKeepsTheOrderAndTheLastErasureEmptiesIt) {
  MemberList m;
  const std::vector<std::int32_t> ids{4, 5, 6, 7};
  m.assign(ids.data(), ids.data() + ids.size());
  m.erase(m.begin() + 1);
  EXPECT_EQ(values(m), (std::vector<std::int32_t>{4, 6, 7}));
  while (!m.empty()) m.erase(m.begin());
  EXPECT_EQ(m.size(), 0u);
  m.push_back(9);
  m.erase(m.begin());
  EXPECT_TRUE(m.empty());
}

TEST(MemberList, RandomOperationsMatchAVector) {
  Random random(11, RandomPurpose::positions);
  auto rng = [&random] { return static_cast<std::uint64_t>(random.uniform() * 0x1.0p40); };
  std::vector<MemberList> lists(8);
  std::vector<std::vector<std::int32_t>> expected(8);
  for (int step = 0; step < 20000; ++step) {
    const int a = static_cast<int>(rng() % 8), b = static_cast<int>(rng() % 8);
    switch (rng() % 6) {
      case 0:
      case 1: {
        const auto id = static_cast<std::int32_t>(rng() % 1000);
        lists[a].push_back(id);
        expected[a].push_back(id);
        break;
      }
      case 2:  // a merge: b's members go to a, b is left empty
        if (a == b) break;
        lists[a].append(lists[b].begin(), lists[b].end());
        lists[b].clear();
        expected[a].insert(expected[a].end(), expected[b].begin(), expected[b].end());
        expected[b].clear();
        break;
      case 3:
        if (expected[a].empty()) break;
        {
          const auto k = static_cast<std::ptrdiff_t>(rng() % expected[a].size());
          lists[a].erase(lists[a].begin() + k);
          expected[a].erase(expected[a].begin() + k);
        }
        break;
      case 4:
        lists[a] = lists[b];
        expected[a] = expected[b];
        break;
      case 5:
        if (a == b) break;
        lists[a] = std::move(lists[b]);
        expected[a] = std::move(expected[b]);
        expected[b].clear();
        EXPECT_TRUE(lists[b].empty());
        break;
    }
    ASSERT_EQ(values(lists[a]), expected[a]) << "step " << step;
    ASSERT_EQ(values(lists[b]), expected[b]) << "step " << step;
    ASSERT_EQ(lists[a].size(), expected[a].size());
  }
}

TEST(MemberList, CopiesAreIndependent) {
  MemberList a;
  for (std::int32_t k = 0; k < 10; ++k) a.push_back(k);
  MemberList b = a;
  b[0] = 100;
  EXPECT_EQ(a.front(), 0);
  EXPECT_EQ(b.front(), 100);
  MemberList c(std::move(b));
  EXPECT_TRUE(b.empty());  // NOLINT(bugprone-use-after-move): a moved-from list is empty
  EXPECT_EQ(c.size(), 10u);
}

}  // namespace
}  // namespace ballagg
