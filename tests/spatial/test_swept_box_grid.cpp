// The grid of swept boxes (swept_box_grid.hpp) against every pair of boxes: each box that
// overlaps another (with periodic faces, one of its images) is among that box's
// candidates, whatever the boxes' sizes (small, elongated, wider than the grid allows).
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/spatial/swept_box_grid.hpp"

namespace ballagg {
namespace {

// Whether two closed intervals [a_lo, a_hi] and [b_lo, b_hi] overlap, on a line or (period
// > 0) on a circle of that length, where b may be shifted by any multiple of it.
bool intervals_overlap(double a_lo, double a_hi, double b_lo, double b_hi, double period) {
  if (period <= 0.0) return a_lo <= b_hi && b_lo <= a_hi;
  const double shift = period * std::floor((a_lo - b_lo) / period);  // b moved to just below a
  for (int k = -1; k <= 2; ++k)
    if (a_lo <= b_hi + shift + k * period && b_lo + shift + k * period <= a_hi) return true;
  return false;
}

template <int D>
bool boxes_overlap(const SweptBox<D>& a, const SweptBox<D>& b, double period) {
  for (int axis = 0; axis < D; ++axis)
    if (!intervals_overlap(a.lo[axis], a.hi[axis], b.lo[axis], b.hi[axis], period)) return false;
  return true;
}

template <int D>
void every_overlapping_box_is_a_candidate(Boundary boundary, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double length = 60.0;
  const Box<D> box{length, boundary};
  std::vector<SweptBox<D>> boxes;
  for (int k = 0; k < 600; ++k) {
    // Positions a little beyond the box too: the centres the retreat reads are not wrapped.
    const Vec<D> at = Vec<D>::NullaryExpr([&] { return -5.0 + (length + 10.0) * unit(rng); });
    const double r = unit(rng) < 0.05 ? 20.0 * unit(rng) : 0.3 + unit(rng);  // a few wide ones
    const Vec<D> flight = Vec<D>::NullaryExpr([&] { return 6.0 * (unit(rng) - 0.5); });
    const Vec<D> to = at + flight;
    boxes.push_back({Vec<D>(at.cwiseMin(to) - Vec<D>::Constant(r)), Vec<D>(at.cwiseMax(to) + Vec<D>::Constant(r))});
  }
  const SweptBoxGrid<D> grid(box, boxes);
  const double period = box.periodic() ? length : 0.0;
  int overlapping = 0, wide = 0;
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    std::vector<std::int32_t> candidates;
    grid.for_each_candidate(k, [&](std::int32_t m) { candidates.push_back(m); });
    std::sort(candidates.begin(), candidates.end());
    for (std::size_t m = 0; m < boxes.size(); ++m) {
      if (m == k || !boxes_overlap<D>(boxes[k], boxes[m], period)) continue;
      ++overlapping;
      EXPECT_TRUE(std::binary_search(candidates.begin(), candidates.end(), static_cast<std::int32_t>(m)))
          << "box " << m << " overlaps box " << k << " but is not its candidate";
    }
    if ((boxes[k].hi - boxes[k].lo).maxCoeff() > 20.0) ++wide;
  }
  EXPECT_GT(overlapping, 1000);  // the boxes crowd each other
  EXPECT_GT(wide, 5);
}

TEST(SweptBoxGrid, EveryOverlappingBoxIsACandidate2DWalls) { every_overlapping_box_is_a_candidate<2>(Boundary::walls, 1); }
TEST(SweptBoxGrid, EveryOverlappingBoxIsACandidate2DPeriodic) {
  every_overlapping_box_is_a_candidate<2>(Boundary::periodic, 2);
}
TEST(SweptBoxGrid, EveryOverlappingBoxIsACandidate3DWalls) { every_overlapping_box_is_a_candidate<3>(Boundary::walls, 3); }
TEST(SweptBoxGrid, EveryOverlappingBoxIsACandidate3DPeriodic) {
  every_overlapping_box_is_a_candidate<3>(Boundary::periodic, 4);
}

// The grid thins the candidates out: in a sparse spread of small boxes, a box has far fewer
// candidates than there are boxes.
TEST(SweptBoxGrid, SmallBoxesHaveFewCandidates) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Box<2> box{400.0, Boundary::walls};
  std::vector<SweptBox<2>> boxes;
  for (int k = 0; k < 4000; ++k) {
    const Vec<2> at(400.0 * unit(rng), 400.0 * unit(rng));
    boxes.push_back({Vec<2>(at - Vec<2>::Constant(1.0)), Vec<2>(at + Vec<2>::Constant(1.0))});
  }
  const SweptBoxGrid<2> grid(box, boxes);
  std::size_t most = 0;
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    std::size_t count = 0;
    grid.for_each_candidate(k, [&](std::int32_t) { ++count; });
    most = std::max(most, count);
  }
  EXPECT_LT(most, 100u);
}

}  // namespace
}  // namespace ballagg
