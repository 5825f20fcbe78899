// The shape indicators of docs/analysis.md against shapes with known answers: gyration
// tensor, aspect ratio (4.3) and orientation (4.4), contacts (4.5), pair distribution
// (4.6), R_max (Richardson 7) and density, the mass spectrum, and clusters cut by periodic
// faces put back in one piece.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "analysis_support.hpp"
#include "ballagg/analysis/aggregate_analysis.hpp"
#include "ballagg/analysis/cluster_unwrapping.hpp"
#include "ballagg/analysis/contacts.hpp"
#include "ballagg/analysis/gyration.hpp"
#include "ballagg/analysis/pair_distribution.hpp"
#include "support.hpp"

using ballagg::Box;
using ballagg::Boundary;
using ballagg::SphereTable;
using ballagg::Vec;
using ballagg::testing::chain;
using ballagg::testing::lattice;
using ballagg::testing::one_cluster;
using ballagg::testing::vec;

namespace {

constexpr double kTight = 1e-12;

// A rectangular grid of nx x ny points with spacing h, rotated by angle theta.
std::vector<Vec<2>> rotated_grid(int nx, int ny, double h, double theta) {
  std::vector<Vec<2>> x;
  const double c = std::cos(theta), s = std::sin(theta);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const double u = h * (i - 0.5 * (nx - 1)), v = h * (j - 0.5 * (ny - 1));
      x.push_back(Vec<2>(50.0 + c * u - s * v, 50.0 + s * u + c * v));
    }
  return x;
}

}  // namespace

TEST(Gyration, GridEigenvaluesAreTheVariancesOfItsSides) {
  // A uniform grid of n points with spacing h has variance h^2 (n^2 - 1) / 12 along a side.
  const int nx = 9, ny = 4;
  const double h = 0.4, theta = 0.3;
  const auto shape = ballagg::gyration_shape<2>(rotated_grid(nx, ny, h, theta));
  const double lx = h * h * (nx * nx - 1) / 12.0, ly = h * h * (ny * ny - 1) / 12.0;
  EXPECT_NEAR(shape.eigenvalues[0], lx, kTight);
  EXPECT_NEAR(shape.eigenvalues[1], ly, kTight);
  EXPECT_NEAR(shape.aspect_ratio, lx / ly, 1e-10);
  EXPECT_NEAR(shape.radius_of_gyration, std::sqrt(lx + ly), kTight);
  // The long side points along (cos theta, sin theta); the sign is the positive one.
  EXPECT_NEAR(shape.orientation()[0], std::cos(theta), 1e-10);
  EXPECT_NEAR(shape.orientation()[1], std::sin(theta), 1e-10);
}

TEST(Gyration, OrientationIsAnAxisWithItsLargestComponentPositive) {
  // Rotated by 180 degrees the grid is the same set: the same axis, not its opposite.
  const auto a = ballagg::gyration_shape<2>(rotated_grid(7, 3, 1.0, 2.0));
  const auto b = ballagg::gyration_shape<2>(rotated_grid(7, 3, 1.0, 2.0 + std::numbers::pi));
  EXPECT_NEAR((a.orientation() - b.orientation()).norm(), 0.0, 1e-10);
  // The 2.0 rad axis (-0.42, 0.91): its largest component, y, is already positive.
  EXPECT_NEAR(a.orientation()[0], std::cos(2.0), 1e-10);
}

TEST(Gyration, RegularPolygonAndRingAreRound) {
  std::vector<Vec<2>> ring;
  const int n = 12;
  const double radius = 3.0;
  for (int k = 0; k < n; ++k)
    ring.push_back(Vec<2>(5.0 + radius * std::cos(2 * std::numbers::pi * k / n), 5.0 + radius * std::sin(2 * std::numbers::pi * k / n)));
  const auto shape = ballagg::gyration_shape<2>(ring);
  EXPECT_EQ(shape.aspect_ratio, 1.0);
  EXPECT_NEAR(shape.radius_of_gyration, radius, kTight);
  EXPECT_NEAR(shape.eigenvalues[0], radius * radius / 2, kTight);
}

TEST(Gyration, StraightChainIsInfinitelyElongated) {
  const auto x = chain<2>(vec<2>(1, 1), vec<2>(1, 1), 10, 0.5);
  const auto shape = ballagg::gyration_shape<2>(x);
  EXPECT_TRUE(std::isinf(shape.aspect_ratio));
  EXPECT_NEAR(shape.orientation()[0], std::sqrt(0.5), kTight);
  EXPECT_NEAR(shape.orientation()[1], std::sqrt(0.5), kTight);
  // n points spaced 2r: variance (2r)^2 (n^2 - 1) / 12.
  EXPECT_NEAR(shape.eigenvalues[0], 1.0 * (100 - 1) / 12.0, kTight);
}

TEST(Gyration, ThreeDimensionalCrossOfSixPoints) {
  // +-a e_x, +-b e_y, +-c e_z: G = diag(a^2, b^2, c^2) / 3.
  const double a = 3.0, b = 2.0, c = 1.0;
  const Vec<3> o(10, 10, 10);
  std::vector<Vec<3>> x = {o + a * Vec<3>::UnitX(), o - a * Vec<3>::UnitX(), o + b * Vec<3>::UnitY(),
                           o - b * Vec<3>::UnitY(), o + c * Vec<3>::UnitZ(), o - c * Vec<3>::UnitZ()};
  const auto shape = ballagg::gyration_shape<3>(x);
  EXPECT_NEAR(shape.eigenvalues[0], a * a / 3, kTight);
  EXPECT_NEAR(shape.eigenvalues[1], b * b / 3, kTight);
  EXPECT_NEAR(shape.eigenvalues[2], c * c / 3, kTight);
  EXPECT_NEAR(shape.aspect_ratio, a * a / (b * b), 1e-12);
  EXPECT_NEAR(shape.orientation()[0], 1.0, kTight);
  EXPECT_NEAR(shape.radius_of_gyration, std::sqrt((a * a + b * b + c * c) / 3), kTight);
}

TEST(Contacts, HexagonalFlowerHasFourSeventhsOfTheMaximum) {
  // A centre and its six touching neighbours: 6 contacts for the centre, 3 for each petal
  // (the centre and two petals): (6 + 6 x 3) / (7 x 6) = 4/7.
  const double r = 0.5;
  std::vector<Vec<2>> x = {vec<2>(5, 5)};
  for (int k = 0; k < 6; ++k)
    x.push_back(vec<2>(5 + 2 * r * std::cos(k * std::numbers::pi / 3), 5 + 2 * r * std::sin(k * std::numbers::pi / 3)));
  const auto a = ballagg::analyze_aggregates<2>(Box<2>{10.0, Boundary::walls}, one_cluster<2>(x, r));
  EXPECT_DOUBLE_EQ(a.contacts, 4.0 / 7.0);
  EXPECT_DOUBLE_EQ(a.clusters[0].contacts, 4.0 / 7.0);
}

TEST(Contacts, CuboctahedralCluster3DCountsTwelveForTheCentre) {
  // A centre and its 12 FCC neighbours (the kissing configuration): the centre touches 12,
  // each neighbour the centre and 4 others: (12 + 12 x 5) / (13 x 12) = 6/13.
  const double r = 0.5, d = 2 * r / std::sqrt(2.0);
  std::vector<Vec<3>> x = {Vec<3>(5, 5, 5)};
  for (int s1 : {-1, 1})
    for (int s2 : {-1, 1}) {
      x.push_back(Vec<3>(5 + s1 * d, 5 + s2 * d, 5));
      x.push_back(Vec<3>(5 + s1 * d, 5, 5 + s2 * d));
      x.push_back(Vec<3>(5, 5 + s1 * d, 5 + s2 * d));
    }
  const auto a = ballagg::analyze_aggregates<3>(Box<3>{10.0, Boundary::walls}, one_cluster<3>(x, r));
  EXPECT_DOUBLE_EQ(a.contacts, 6.0 / 13.0);
}

TEST(Contacts, ThresholdIsAlphaRTimesTheRadius) {
  // Two spheres 2.09 R apart are in contact (alpha_R = 2.1), two 2.11 R apart are not;
  // spheres of different clusters count for the box, not for either cluster.
  const double r = 1.0;
  SphereTable<2> t;
  ballagg::testing::add_spheres<2>(t, {vec<2>(2, 2), vec<2>(2 + 2.09 * r, 2)}, r, 0);
  ballagg::testing::add_spheres<2>(t, {vec<2>(2, 8), vec<2>(2 + 2.11 * r, 8)}, r, 1);
  ballagg::testing::add_spheres<2>(t, {vec<2>(8, 2)}, r, 2);
  ballagg::testing::add_spheres<2>(t, {vec<2>(8 + 2.0 * r, 2)}, r, 3);
  const auto a = ballagg::analyze_aggregates<2>(Box<2>{20.0, Boundary::walls}, t);
  EXPECT_DOUBLE_EQ(a.contacts, 4.0 / (6 * 6));  // two pairs in contact: 4 ordered pairs
  EXPECT_DOUBLE_EQ(a.clusters[0].contacts, 2.0 / (2 * 6));
  EXPECT_DOUBLE_EQ(a.clusters[1].contacts, 0.0);
  EXPECT_DOUBLE_EQ(a.clusters[2].contacts, 0.0);
}

TEST(PairDistribution, ChainCountsTheSpheresWithinEachDistance) {
  // n spheres in a line, spaced s R: P(r) = (2/n) sum_{k >= 1, k s R <= r} (n - k). The
  // spacing 2.03 R keeps every distance away from the table's multiples of R/4.
  const int n = 15;
  const double r = 0.2, s = 2.03;
  const auto a = ballagg::analyze_aggregates<2>(
      Box<2>{20.0, Boundary::walls}, one_cluster<2>(chain<2>(vec<2>(1, 1), vec<2>(1, 0), n, 0.5 * s * r), r));
  const auto& p = a.pair_distribution;
  ASSERT_EQ(p.r.size(), 65u);
  EXPECT_DOUBLE_EQ(p.r.front(), 4 * r);
  EXPECT_DOUBLE_EQ(p.r.back(), 20 * r);
  for (std::size_t k = 0; k < p.r.size(); ++k) {
    double expected = 0.0;
    for (int j = 1; j < n; ++j)
      if (s * j <= p.r[k] / r) expected += 2.0 * (n - j) / n;
    EXPECT_DOUBLE_EQ(p.all[k], expected) << "r = " << p.r[k] / r << " R";
    EXPECT_DOUBLE_EQ(p.cluster[k], expected);
  }
}

TEST(PairDistribution, PeriodicPairsAreMinimumImages) {
  // Two spheres on either side of a periodic face, 3R apart through it.
  const double r = 1.0, l = 100.0;
  const auto a = ballagg::analyze_aggregates<2>(Box<2>{l, Boundary::periodic},
                                                one_cluster<2>({vec<2>(1.5, 50), vec<2>(l - 1.5, 50)}, 1.5 * r));
  EXPECT_DOUBLE_EQ(a.pair_distribution.all.front(), 1.0);  // within 4R: each has the other
}

TEST(MassRadius, ChainHasRMaxOfHalfItsLengthAndTheDensityOfItsDisc) {
  // n touching spheres: centre of mass in the middle, R_max = (n - 1) R + R = n R.
  const int n = 11;
  const double r = 0.3;
  const auto a = ballagg::analyze_aggregates<2>(Box<2>{20.0, Boundary::walls},
                                                one_cluster<2>(chain<2>(vec<2>(2, 3), vec<2>(0.6, 0.8), n, r), r));
  const auto& c = a.clusters[0];
  EXPECT_NEAR(c.r_max, n * r, 1e-12);
  EXPECT_NEAR(c.density, n / (std::numbers::pi * n * r * n * r), 1e-12);
  EXPECT_DOUBLE_EQ(c.mass, n);
  EXPECT_EQ(c.size, n);
  EXPECT_DOUBLE_EQ(c.contacts, 2.0 * (n - 1) / (6.0 * n));
}

TEST(MassSpectrum, CountsClustersOfEachSize) {
  SphereTable<2> t;
  const double r = 0.5;
  ballagg::testing::add_spheres<2>(t, chain<2>(vec<2>(1, 1), vec<2>(1, 0), 3, r), r, 7);
  ballagg::testing::add_spheres<2>(t, chain<2>(vec<2>(1, 5), vec<2>(1, 0), 3, r), r, 4);
  ballagg::testing::add_spheres<2>(t, {vec<2>(9, 9)}, r, 1);
  ballagg::testing::add_spheres<2>(t, chain<2>(vec<2>(1, 12), vec<2>(1, 0), 5, r), r, 2);
  const auto a = ballagg::analyze_aggregates<2>(Box<2>{20.0, Boundary::walls}, t);
  ASSERT_EQ(a.mass_spectrum.size(), 3u);
  EXPECT_EQ(a.mass_spectrum[0].size, 1);
  EXPECT_EQ(a.mass_spectrum[0].clusters, 1);
  EXPECT_EQ(a.mass_spectrum[1].size, 3);
  EXPECT_EQ(a.mass_spectrum[1].clusters, 2);
  EXPECT_EQ(a.mass_spectrum[2].size, 5);
  EXPECT_EQ(a.largest, 3);  // clusters in order of their first sphere
}

TEST(Unwrapping, ClusterCutByPeriodicFacesHasTheShapeOfTheWholeOne) {
  // An L-shaped cluster in the middle of the box, then moved so that it straddles both
  // periodic faces (the file folds its centres into the box): same shape, same sizes.
  const double r = 0.5, l = 30.0;
  std::vector<Vec<2>> x = chain<2>(vec<2>(14, 14), vec<2>(1, 0), 8, r);
  for (const Vec<2>& p : chain<2>(vec<2>(14, 15), vec<2>(0, 1), 5, r)) x.push_back(p);
  const Box<2> box{l, Boundary::periodic};
  const auto whole = ballagg::analyze_aggregates<2>(box, one_cluster<2>(x, r));
  std::vector<Vec<2>> cut;
  for (const Vec<2>& p : x) cut.push_back(box.wrap(Vec<2>(p + vec<2>(l / 2 - 3, l / 2 - 1))));
  const auto split = ballagg::analyze_aggregates<2>(box, one_cluster<2>(cut, r));
  const auto &a = whole.clusters[0], &b = split.clusters[0];
  EXPECT_FALSE(b.percolating);
  EXPECT_NEAR(a.shape.radius_of_gyration, b.shape.radius_of_gyration, 1e-12);
  EXPECT_NEAR(a.shape.aspect_ratio, b.shape.aspect_ratio, 1e-9);
  EXPECT_NEAR(a.r_max, b.r_max, 1e-12);
  EXPECT_NEAR((a.shape.orientation() - b.shape.orientation()).norm(), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(a.contacts, b.contacts);
  // The centroid is the folded image of the whole cluster's.
  EXPECT_NEAR((box.wrap(Vec<2>(a.shape.centroid + vec<2>(l / 2 - 3, l / 2 - 1))) - b.shape.centroid).norm(), 0.0, 1e-9);
}

TEST(Unwrapping, ClusterAroundThePeriodicBoxIsPercolating) {
  // A closed ring of touching spheres all around the box along x.
  const double r = 0.5;
  const int n = 20;
  const Box<3> box{2 * r * n, Boundary::periodic};
  const auto a = ballagg::analyze_aggregates<3>(box, one_cluster<3>(chain<3>(Vec<3>(0.5, 3, 3), Vec<3>::UnitX(), n, r), r));
  EXPECT_TRUE(a.clusters[0].percolating);
  EXPECT_DOUBLE_EQ(a.clusters[0].contacts, 2.0 / 12.0);  // every sphere has two neighbours
}

TEST(Unwrapping, WallsLeaveCentresAlone) {
  const std::vector<Vec<2>> x = chain<2>(vec<2>(1, 1), vec<2>(1, 0), 4, 0.5);
  const auto p = ballagg::partition_clusters({3, 3, 3, 3}, 4);
  const auto u = ballagg::unwrap_clusters<2>(Box<2>{10.0, Boundary::walls}, x, {0.5, 0.5, 0.5, 0.5}, p);
  EXPECT_EQ(u.position, x);
  EXPECT_EQ(p.n_clusters(), 1);
}
