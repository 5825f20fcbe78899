// The fractal dimensions against sets of known dimension, as in Fig. 10 of Degond et al.
// 2023: spheres on lines (1), a filled lattice (2, and 3 in 3D), a Sierpinski triangle
// (log 3 / log 2), by box counting (4.7) and by mass-radius (Richardson 1995 §3).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "analysis_support.hpp"
#include "ballagg/analysis/box_counting.hpp"
#include "support.hpp"

using ballagg::Box;
using ballagg::Boundary;
using ballagg::Vec;
using ballagg::testing::chain;
using ballagg::testing::lattice;
using ballagg::testing::one_cluster;
using ballagg::testing::vec;

namespace {

// The and the paper's tolerance for the validation set.
constexpr double kDimensionTolerance = 0.05;

template <int D>
ballagg::AggregateAnalysis<D> analyze(double box_length, const std::vector<Vec<D>>& x, double r) {
  return ballagg::analyze_aggregates<D>(Box<D>{box_length, Boundary::walls}, one_cluster<D>(x, r));
}

}  // namespace

TEST(BoxCounting, ThreeLinesOfSpheresAreOneDimensional) {
  // Three horizontal lines of touching spheres across the box (Fig. 10, left), L = 120.
  // At eps = L/2 the three lines fall into two rows of cells, which tilts the fit: 1.063
  // with the paper's 900 spheres (R = 0.2, 7 levels), 1.039 with 3000 (R = 0.06, 9 levels).
  const double l = 120.0, r = 0.06;
  std::vector<Vec<2>> x;
  for (double y : {l / 6, l / 2, 5 * l / 6})
    for (const Vec<2>& p : chain<2>(vec<2>(r, y), vec<2>(1, 0), 1000, r)) x.push_back(p);
  const auto a = analyze<2>(l, x, r);
  EXPECT_NEAR(a.box_counting.dimension, 1.0, kDimensionTolerance);
  EXPECT_LT(a.box_counting.dimension_error, 0.05);
}

TEST(BoxCounting, OneLineAcrossTheBoxIsExactlyOneDimensional) {
  const double l = 120.0, r = 0.2;
  const auto a = analyze<2>(l, chain<2>(vec<2>(r, 37.0), vec<2>(1, 0), 300, r), r);
  EXPECT_NEAR(a.box_counting.dimension, 1.0, 1e-12);
}

TEST(BoxCounting, FilledSquareLatticeIsTwoDimensional) {
  // 30 x 30 touching spheres filling the box (Fig. 10, middle): N(eps) = (L / eps)^2
  // exactly while a cell holds at least one centre, so D_f = 2 and a = L^2.
  const double l = 120.0, r = 2.0;
  const auto a = analyze<2>(l, lattice<2>(vec<2>(r, r), 30, r), r);
  EXPECT_NEAR(a.box_counting.dimension, 2.0, 1e-12);
  EXPECT_NEAR(a.box_counting.prefactor, l * l, 1e-8 * l * l);
  // The table: the fitted levels are those with 3R <= eps <= L/2.
  for (std::size_t k = 0; k < a.box_counting.level.size(); ++k) {
    const double eps = a.box_counting.eps[k];
    EXPECT_EQ(static_cast<bool>(a.box_counting.fitted[k]), eps >= 3 * r && eps <= l / 2) << eps;
    EXPECT_DOUBLE_EQ(eps, l / std::pow(2.0, a.box_counting.level[k]));
  }
}

TEST(BoxCounting, FilledCubicLatticeIsThreeDimensional) {
  const double l = 32.0, r = 1.0;
  const auto a = analyze<3>(l, lattice<3>(Vec<3>(r, r, r), 16, r), r);
  EXPECT_NEAR(a.box_counting.dimension, 3.0, 1e-12);
}

TEST(BoxCounting, SierpinskiTriangleHasDimensionLog3OverLog2) {
  // 3^7 = 2187 touching spheres in an equilateral Sierpinski triangle of 128 rows (Fig. 10,
  // right), in a box one row wider than the triangle.
  const double r = 0.5, l = 2 * r * 129;
  const auto a = analyze<2>(l, ballagg::testing::sierpinski(vec<2>(r, r), 7, r), r);
  EXPECT_NEAR(a.box_counting.dimension, std::log(3.0) / std::log(2.0), kDimensionTolerance);
}

TEST(BoxCounting, OneSortServesEveryLevel) {
  // Counts of a random cloud against a direct count of the distinct cells at each level.
  const double l = 10.0;
  std::vector<Vec<2>> x;
  std::uint64_t s = 12345;
  auto uniform = [&] { s = s * 6364136223846793005ULL + 1442695040888963407ULL; return (s >> 11) * 0x1.0p-53; };
  for (int k = 0; k < 5000; ++k) x.push_back(vec<2>(l * uniform(), l * uniform()));
  const auto b = ballagg::box_counting<2>(Box<2>{l, Boundary::walls}, x, 0.01);
  for (std::size_t k = 0; k < b.level.size(); ++k) {
    const double cells = std::ldexp(1.0, b.level[k]);
    std::vector<std::pair<long, long>> ids;
    for (const Vec<2>& p : x) ids.emplace_back(static_cast<long>(p[0] / l * cells), static_cast<long>(p[1] / l * cells));
    std::sort(ids.begin(), ids.end());
    EXPECT_EQ(b.boxes[k], std::unique(ids.begin(), ids.end()) - ids.begin()) << "level " << b.level[k];
  }
}

TEST(MassRadius, LineOfSpheresIsOneDimensional) {
  const double r = 0.2;
  const auto a = analyze<2>(120.0, chain<2>(vec<2>(10, 50), vec<2>(1, 0.2), 250, r), r);
  EXPECT_NEAR(a.clusters[0].mass_radius_dimension, 1.0, kDimensionTolerance);
  EXPECT_LT(a.clusters[0].mass_radius_dimension_error, 0.05);
}

TEST(MassRadius, FilledLatticeIsTwoDimensionalAndThreeIn3D) {
  const double r = 0.2;
  const auto a2 = analyze<2>(40.0, lattice<2>(vec<2>(5, 5), 60, r), r);
  EXPECT_NEAR(a2.clusters[0].mass_radius_dimension, 2.0, kDimensionTolerance);
  const auto a3 = analyze<3>(20.0, lattice<3>(Vec<3>(2, 2, 2), 16, r), r);
  EXPECT_NEAR(a3.clusters[0].mass_radius_dimension, 3.0, kDimensionTolerance);
}

TEST(CorrelationDimension, SlopeOfThePairDistributionOfLinesAndLattices) {
  // P(r) of a line grows like r, of a filled lattice like r^2, up to the discreteness of
  // touching spheres over 4R ... 20R: P of a chain is a staircase with steps every 2R,
  // which the fit sees as 1.095 (tolerance 0.1); the square gives 1.955.
  const double r = 0.2;
  const auto line = analyze<2>(120.0, chain<2>(vec<2>(10, 50), vec<2>(1, 0), 250, r), r);
  EXPECT_NEAR(line.pair_distribution.all_fit->slope, 1.0, 0.1);
  const auto square = analyze<2>(40.0, lattice<2>(vec<2>(5, 5), 60, r), r);
  EXPECT_NEAR(square.pair_distribution.all_fit->slope, 2.0, kDimensionTolerance);
  EXPECT_NEAR(square.pair_distribution.cluster_fit->slope, 2.0, kDimensionTolerance);
}

TEST(MassRadius, SmallClustersHaveNoDimension) {
  const double r = 0.5;
  const auto a = analyze<2>(20.0, chain<2>(vec<2>(2, 2), vec<2>(1, 0), 5, r), r);
  EXPECT_TRUE(std::isnan(a.clusters[0].mass_radius_dimension));
  EXPECT_TRUE(std::isnan(a.clusters[0].box_dimension));
}

// Richardson's estimate: log n(r_i) against log r_i through every centre. A line and
// round (filled disc, filled ball) sets of spheres, where n(r) grows as r^d right to the
// edge, give their dimension (the windowed fit is tested above); an aggregate needs
// kRichardsonMinSize spheres.
template <int D>
std::vector<Vec<D>> filled_ball(double radius, double r) {
  std::vector<Vec<D>> x;
  const Vec<D> centre = Vec<D>::Constant(50.0);
  for (const Vec<D>& p : lattice<D>(Vec<D>::Constant(50.0 - radius), static_cast<int>(radius / r) + 1, r))
    if ((p - centre).norm() <= radius) x.push_back(p);
  return x;
}

TEST(RichardsonDimension, LineDiscAndBallHaveTheirDimension) {
  const double r = 0.5;
  const auto line = analyze<2>(300.0, chain<2>(vec<2>(10, 50), vec<2>(1, 0.2), 251, r), r);
  EXPECT_NEAR(line.clusters[0].richardson_dimension, 1.0, kDimensionTolerance);
  const auto disc = analyze<2>(100.0, filled_ball<2>(30.0, r), r);
  EXPECT_NEAR(disc.clusters[0].richardson_dimension, 2.0, kDimensionTolerance);
  const auto ball = analyze<3>(100.0, filled_ball<3>(12.0, r), r);
  // The first shells of the cubic lattice hold more centres than r^3 (7 within one
  // spacing, against 4/3 pi): the fit through every centre sees 2.92.
  EXPECT_NEAR(ball.clusters[0].richardson_dimension, 3.0, 0.1);
  EXPECT_GT(ball.clusters[0].richardson_dimension_error, 0.0);
  const auto three = analyze<2>(20.0, chain<2>(vec<2>(2, 2), vec<2>(1, 0), ballagg::kRichardsonMinSize - 1, r), r);
  EXPECT_TRUE(std::isnan(three.clusters[0].richardson_dimension));
  const auto four = analyze<2>(20.0, chain<2>(vec<2>(2, 2), vec<2>(1, 0), ballagg::kRichardsonMinSize, r), r);
  EXPECT_TRUE(std::isfinite(four.clusters[0].richardson_dimension));
}
