// The dynamical indicators of `ballagg analyze` (Richardson 1995 §3): each cluster's
// velocity, spin and kinetic energies of translation and rotation (eq. 2 with the inertia
// tensor of eq. 1) against hand-computed bodies, the mass spectrum of coalesced spheres,
// and the inverse-square-weighted mean fractal dimension.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "analysis_support.hpp"
#include "ballagg/analysis/aggregate_analysis.hpp"
#include "ballagg/analysis/mass_spectrum.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::add_spheres;
using testing::chain;
using testing::lattice;
using testing::vec;

// A dimer of touching unit-mass spheres (radius 1/2) along x, every sphere carrying the
// centre-of-mass velocity v and the cluster's spin w, as in final.csv.
template <int D>
SphereTable<D> spinning_dimer(const Vec<D>& first, const Vec<D>& second, const Vec<D>& v, const Spin<D>& w) {
  SphereTable<D> t;
  add_spheres<D>(t, {first, second}, 0.5, 0);
  t.velocity.assign(2, v);
  t.spin.assign(2, w);
  return t;
}

TEST(ClusterMotion, SpinningDimerHasTheEnergiesOfEquations1And2) {
  // About the centre of mass: I_xx = 2 (2/5 m R^2) = 0.2 (along the axis), I_yy = I_zz =
  // 2 m (1/2)^2 + 0.2 = 0.7. With omega = (3, 0, 2): E_rot = (0.2 * 9 + 0.7 * 4) / 2 = 2.3.
  const Vec<3> v(0.3, -0.2, 0.1);
  const auto a = analyze_aggregates<3>(Box<3>{10.0, Boundary::walls},
                                       spinning_dimer<3>(vec<3>(4, 5, 5), vec<3>(5, 5, 5), v, Spin<3>(3, 0, 2)));
  ASSERT_EQ(a.clusters.size(), 1u);
  const ClusterMotion<3>& m = a.clusters[0].motion;
  EXPECT_LT((m.velocity - v).norm(), 1e-15);
  EXPECT_NEAR(m.translational_energy, 0.5 * 2.0 * v.squaredNorm(), 1e-15);
  EXPECT_NEAR(m.rotational_energy, 2.3, 1e-14);
  EXPECT_NEAR(m.spin(), std::sqrt(13.0), 1e-15);
  EXPECT_NEAR(a.rotational_energy, 2.3, 1e-14);
}

TEST(ClusterMotion, DiscDimerAcrossPeriodicFacesSpinsAboutItsWholeCentre) {
  // Discs: I = 2 m (1/2)^2 + 2 (1/2 m R^2) = 0.75; omega = 2 gives E_rot = 1.5. The dimer
  // straddles the periodic face: its inertia is that of the dimer in one piece.
  const auto a = analyze_aggregates<2>(Box<2>{10.0, Boundary::periodic},
                                       spinning_dimer<2>(vec<2>(9.8, 5), vec<2>(0.8, 5), Vec<2>(0.1, 0.0), Spin<2>(2.0)));
  ASSERT_EQ(a.clusters.size(), 1u);
  EXPECT_NEAR(a.clusters[0].motion.rotational_energy, 1.5, 1e-13);
  EXPECT_DOUBLE_EQ(a.clusters[0].motion.spin(), 2.0);
}

TEST(ClusterMotion, WithoutSpinColumnsClustersOnlyTranslate) {
  SphereTable<3> t = spinning_dimer<3>(vec<3>(4, 5, 5), vec<3>(5, 5, 5), Vec<3>(1, 0, 0), Spin<3>::Zero());
  t.spin.clear();
  const auto a = analyze_aggregates<3>(Box<3>{10.0, Boundary::walls}, t);
  EXPECT_EQ(a.clusters[0].motion.rotational_energy, 0.0);
  EXPECT_EQ(a.clusters[0].motion.spin(), 0.0);
  EXPECT_DOUBLE_EQ(a.translational_energy, 1.0);
}

TEST(MassSpectrum, CoalescedSpheresAreCountedByMass) {
  // Richardson's models i-ii: every body is one sphere; the spectrum is one of masses.
  // Masses equal but for round-off (0.1 + 0.2 and 0.3) share a bin.
  const auto bins = mass_spectrum({{1, 2.0}, {1, 1.0}, {1, 3.0}, {1, 2.0}, {1, 0.1 + 0.2}, {1, 0.3}, {2, 2.0}});
  ASSERT_EQ(bins.size(), 5u);
  EXPECT_EQ(bins[0].size, 1);
  EXPECT_DOUBLE_EQ(bins[0].mass, 0.3);
  EXPECT_EQ(bins[0].clusters, 2);
  EXPECT_EQ(bins[1].mass, 1.0);
  EXPECT_EQ(bins[1].clusters, 1);
  EXPECT_EQ(bins[2].mass, 2.0);
  EXPECT_EQ(bins[2].clusters, 2);
  EXPECT_EQ(bins[3].mass, 3.0);
  EXPECT_EQ(bins[4].size, 2);  // the same mass in two spheres: another bin
}

TEST(PopulationFits, MeanFractalDimensionWeighsEachClusterByItsInverseSquareError) {
  // Two identical filled squares: the mean is their dimension, with no spread. A straight
  // chain added: the mean moves between the two dimensions, towards the better-fitted one.
  SphereTable<2> t;
  add_spheres<2>(t, lattice<2>(vec<2>(5, 5), 14, 0.5), 0.5, 0);
  add_spheres<2>(t, lattice<2>(vec<2>(40, 40), 14, 0.5), 0.5, 1);
  const auto squares = analyze_aggregates<2>(Box<2>{100.0, Boundary::walls}, t);
  const double square = squares.clusters[0].mass_radius_dimension;
  const WeightedMean& same = squares.population.mass_radius_dimension;
  EXPECT_EQ(same.clusters, 2);
  EXPECT_NEAR(same.mean, square, 1e-12);
  EXPECT_NEAR(same.spread, 0.0, 1e-6);

  add_spheres<2>(t, chain<2>(vec<2>(5, 70), vec<2>(1, 0), 60, 0.5), 0.5, 2);
  const auto mixed = analyze_aggregates<2>(Box<2>{100.0, Boundary::walls}, t);
  const ClusterSummary<2>& line = mixed.clusters[2];
  const WeightedMean& p = mixed.population.mass_radius_dimension;
  EXPECT_EQ(p.clusters, 3);
  EXPECT_GT(p.mean, std::min(square, line.mass_radius_dimension));
  EXPECT_LT(p.mean, std::max(square, line.mass_radius_dimension));
  const double w_square = 1.0 / std::pow(squares.clusters[0].mass_radius_dimension_error, 2),
               w_line = 1.0 / std::pow(line.mass_radius_dimension_error, 2);
  EXPECT_NEAR(p.mean, (2 * w_square * square + w_line * line.mass_radius_dimension) / (2 * w_square + w_line), 1e-12);
  EXPECT_GT(p.spread, 0.0);
  // Richardson's estimate is averaged the same way.
  EXPECT_EQ(mixed.population.richardson_dimension.clusters, 3);
}

}  // namespace
}  // namespace ballagg
