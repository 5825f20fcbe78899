// SparseRecords keeps a record for some ids only: found where stored, absent elsewhere,
// places of forgotten records taken again last freed first, and ids added or reset.
#include <gtest/gtest.h>

#include "ballagg/core/sparse_records.hpp"

namespace ballagg {
namespace {

TEST(SparseRecords, FindsWhatIsStoredAndNothingElse) {
  SparseRecords<double> r;
  r.reset(5);
  EXPECT_EQ(r.ids(), 5u);
  for (std::size_t c = 0; c < 5; ++c) EXPECT_EQ(r.find(c), nullptr);
  r.store(3, 1.5);
  r.store(1, 2.5);
  r.store(3, 4.5);  // stored again: replaced, not added
  ASSERT_NE(r.find(3), nullptr);
  EXPECT_EQ(*r.find(3), 4.5);
  EXPECT_EQ(*r.find(1), 2.5);
  EXPECT_EQ(r.find(0), nullptr);
  r.forget(3);
  r.forget(3);  // nothing left to forget
  r.forget(4);
  EXPECT_EQ(r.find(3), nullptr);
  EXPECT_EQ(*r.find(1), 2.5);
}

// A forgotten record's place is taken again (no growth), the last freed first, so that
// the layout depends on the order of the calls alone.
TEST(SparseRecords, TakesFreedPlacesAgainLastFreedFirst) {
  SparseRecords<int> r;
  r.reset(6);
  for (int c = 0; c < 4; ++c) r.store(static_cast<std::size_t>(c), c);
  const int* place_of_1 = r.find(1);
  const int* place_of_2 = r.find(2);
  r.forget(1);
  r.forget(2);
  r.store(5, 50);  // takes 2's place, freed last
  r.store(4, 40);  // then 1's
  EXPECT_EQ(r.find(5), place_of_2);
  EXPECT_EQ(r.find(4), place_of_1);
  EXPECT_EQ(*r.find(0), 0);
  EXPECT_EQ(*r.find(3), 3);
}

TEST(SparseRecords, GrowsWithoutRecordsAndResetsToNone) {
  SparseRecords<int> r;
  r.reset(2);
  r.store(1, 7);
  r.resize(4);
  EXPECT_EQ(r.ids(), 4u);
  EXPECT_EQ(*r.find(1), 7);
  EXPECT_EQ(r.find(3), nullptr);
  r.store(3, 9);
  EXPECT_EQ(*r.find(3), 9);
  r.reset(3);
  for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(r.find(c), nullptr);
}

}  // namespace
}  // namespace ballagg
