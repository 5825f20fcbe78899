// The cell lists of spatial/: the geometry of the grid, the sorted cell list's segment
// queries and parallel build, and the movable cell list's re-binned items.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>

#include <gtest/gtest.h>
#include <omp.h>

#include "ballagg/spatial/grid_geometry.hpp"
#include "ballagg/spatial/movable_cell_list.hpp"
#include "ballagg/spatial/sorted_cell_list.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

// The distance from p to the segment from a to a + d; in a periodic box, to its nearest
// image (images up to three box lengths away, enough for the segments below).
template <int D>
double distance_to_segment(const Box<D>& box, const Vec<D>& p, const Vec<D>& a, const Vec<D>& d) {
  const int images = box.periodic() ? 3 : 0;
  double best = 1e300;
  std::array<int, D> n;
  n.fill(-images);
  while (true) {
    Vec<D> q = p;
    for (int k = 0; k < D; ++k) q[k] += n[k] * box.length;
    const double t = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (q - a - t * d).norm());
    int k = 0;
    while (k < D && ++n[k] > images) n[k] = -images, ++k;
    if (k == D) return best;
  }
}

// The retreat's narrow search (retreat.cpp): every point within the radius of a segment
// is reported (each once), as a brute force finds. Points a little beyond a wall (where a minimisation can push a
// sphere) and segments wrapping round a periodic box included.
template <int D>
void segment_query_finds_every_point_near_the_segment(Boundary boundary) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double length = 20.0;
  const Box<D> box{length, boundary};
  std::vector<Vec<D>> points(1500);
  for (Vec<D>& p : points)
    for (int a = 0; a < D; ++a) {
      p[a] = length * unit(rng);
      if (boundary == Boundary::walls && unit(rng) < 0.02) p[a] = a % 2 ? -0.3 * unit(rng) : length + 0.3 * unit(rng);
    }
  SortedCellList<D> cells(box, 0.6, static_cast<int>(points.size()));
  cells.build(points);
  for (int trial = 0; trial < 100; ++trial) {
    Vec<D> a, d;
    for (int k = 0; k < D; ++k) {
      a[k] = length * (1.2 * unit(rng) - 0.1);
      d[k] = (trial % 10 == 0 ? 2.0 * length : 6.0) * (unit(rng) - 0.5);
    }
    const double radius = 0.3 + unit(rng);
    std::set<int> expected, got;
    for (int i = 0; i < static_cast<int>(points.size()); ++i) {
      if (distance_to_segment(box, points[i], a, d) < radius) expected.insert(i);
    }
    cells.for_each_near_segment(a, d, radius, [&](int i) { EXPECT_TRUE(got.insert(i).second) << "point " << i << " twice"; });
    for (int i : expected) EXPECT_TRUE(got.count(i)) << "point " << i << " missed, trial " << trial;
  }
}

// The centre of each cell is binned in that cell, and its neighbours are the cells of the
// points around it (what the engine's marks of spheres beyond the skin rely on).
template <int D>
void cell_centres_are_in_their_cells(Boundary boundary) {
  Box<D> box;
  box.length = 7.3;
  box.boundary = boundary;
  const GridGeometry<D> grid(box, 1.0, 1000);
  ASSERT_EQ(grid.per_side(), 7);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> within(-0.5, 0.5);
  for (std::int64_t cell = 0; cell < grid.n_cells(); ++cell) {
    const Vec<D> centre = grid.centre(cell);
    EXPECT_EQ(grid.cell_index(centre), cell);
    // Any point of the cell has the same neighbouring cells as its centre.
    Vec<D> p = centre;
    for (int a = 0; a < D; ++a) p[a] += within(rng) * grid.cell_size();
    std::set<std::int64_t> from_centre, from_point;
    grid.for_each_cell_near(centre, [&](std::int64_t c) { from_centre.insert(c); });
    grid.for_each_cell_near(p, [&](std::int64_t c) { from_point.insert(c); });
    EXPECT_EQ(from_centre, from_point);
  }
}

TEST(GridGeometry, TheCentreOfACellIsInThatCell) {
  cell_centres_are_in_their_cells<2>(Boundary::walls);
  cell_centres_are_in_their_cells<2>(Boundary::periodic);
  cell_centres_are_in_their_cells<3>(Boundary::walls);
  cell_centres_are_in_their_cells<3>(Boundary::periodic);
}

TEST(SortedCellList, SegmentQueryFindsEveryPointNearTheSegment) {
  segment_query_finds_every_point_near_the_segment<2>(Boundary::walls);
  segment_query_finds_every_point_near_the_segment<2>(Boundary::periodic);
  segment_query_finds_every_point_near_the_segment<3>(Boundary::walls);
  segment_query_finds_every_point_near_the_segment<3>(Boundary::periodic);
}

// MovableCellList: after a build and then moves of single items (some far, some several
// times, some back to their first cell), every query finds each item whose current place
// is within reach exactly once, as a brute force over the current places does, and a
// rebuild forgets the moves.
template <int D>
void moved_items_are_found_where_they_are(Boundary boundary) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double length = 15.0;
  const Box<D> box{length, boundary};
  auto random_point = [&] {
    Vec<D> p;
    for (int a = 0; a < D; ++a) p[a] = length * unit(rng);
    return p;
  };
  std::vector<Vec<D>> points(1200);
  for (Vec<D>& p : points) p = random_point();
  MovableCellList<D> cells(box, 0.7, static_cast<int>(points.size()));
  cells.build(points);
  auto check = [&](int trial) {
    const Vec<D> p = random_point();
    Vec<D> d;
    for (int a = 0; a < D; ++a) d[a] = 4.0 * (unit(rng) - 0.5);
    const double radius = 0.2 + 1.5 * unit(rng);
    std::set<int> near, within, along;
    cells.for_each_near(p, [&](int i) { EXPECT_TRUE(near.insert(i).second) << "near: item " << i << " twice"; });
    cells.for_each_within(p, radius, [&](int i) { EXPECT_TRUE(within.insert(i).second) << "within: " << i << " twice"; });
    cells.for_each_near_segment(p, d, radius, [&](int i) { EXPECT_TRUE(along.insert(i).second) << "segment: " << i << " twice"; });
    for (int i = 0; i < static_cast<int>(points.size()); ++i) {
      const double r = box.separation(points[i], p).norm();
      if (r < cells.cell_size()) {
        EXPECT_TRUE(near.count(i)) << "near: item " << i << " missed, trial " << trial;
      }
      if (r < radius) {
        EXPECT_TRUE(within.count(i)) << "within: item " << i << " missed, trial " << trial;
      }
      if (distance_to_segment(box, points[i], p, d) < radius) {
        EXPECT_TRUE(along.count(i)) << "segment: item " << i << " missed, trial " << trial;
      }
    }
  };
  for (int round = 0; round < 40; ++round) {
    for (int k = 0; k < 25; ++k) {
      const int i = static_cast<int>(rng() % points.size());
      const Vec<D> before = points[i];
      points[i] = k % 5 == 0 ? before : random_point();  // some stay in the cell they moved to
      cells.move(i, points[i]);
    }
    check(round);
  }
  EXPECT_GT(cells.n_moved(), 500u);
  cells.build(points);
  EXPECT_EQ(cells.n_moved(), 0u);
  for (int trial = 0; trial < 20; ++trial) check(100 + trial);
}

TEST(MovableCellList, MovedItemsAreFoundWhereTheyAreAndOnlyThere) {
  moved_items_are_found_where_they_are<2>(Boundary::walls);
  moved_items_are_found_where_they_are<2>(Boundary::periodic);
  moved_items_are_found_where_they_are<3>(Boundary::walls);
  moved_items_are_found_where_they_are<3>(Boundary::periodic);
}

// The counting sort of SortedCellList shared among threads leaves every item in the slot
// the serial sort gives it (a cell's items in increasing id), so nothing downstream can
// tell how many threads built the list.
template <int D>
void parallel_build_matches_serial_build(Boundary boundary) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double length = D == 2 ? 60.0 : 16.0;
  const Box<D> box{length, boundary};
  std::vector<Vec<D>> points(3 * kParallelLoopMin);
  for (Vec<D>& p : points)
    for (int a = 0; a < D; ++a) p[a] = length * unit(rng);
  auto build_on = [&](int threads) {
    const int previous = omp_get_max_threads();
    omp_set_num_threads(threads);
    SortedCellList<D> cells(box, 0.9, static_cast<int>(points.size()));
    cells.build(points);
    omp_set_num_threads(previous);
    return cells;
  };
  const SortedCellList<D> serial = build_on(1), parallel = build_on(2);
  ASSERT_EQ(serial.order(), parallel.order());
  for (std::int64_t c = 0; c <= serial.n_cells(); ++c) ASSERT_EQ(serial.first_slot(c), parallel.first_slot(c));
  for (std::int64_t c = 0; c < parallel.n_cells(); ++c)
    for (std::int32_t k = parallel.first_slot(c); k < parallel.first_slot(c + 1); ++k) {
      const int i = parallel.order()[k];
      EXPECT_EQ(parallel.grid().cell_index(points[i]), c);
      EXPECT_EQ(parallel.sorted_position(k), points[i]);
      if (k > parallel.first_slot(c)) {
        EXPECT_LT(parallel.order()[k - 1], i);
      }
    }
}

TEST(SortedCellList, BuildOnTwoThreadsGivesTheSerialSlots) {
  parallel_build_matches_serial_build<2>(Boundary::walls);
  parallel_build_matches_serial_build<2>(Boundary::periodic);
  parallel_build_matches_serial_build<3>(Boundary::periodic);
}

// Whether two regions meet: their intervals overlap on every axis (in a periodic box, for

}  // namespace
}  // namespace ballagg
