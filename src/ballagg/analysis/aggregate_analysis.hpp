#pragma once
// Every indicator of the aggregates of one state (docs/analysis.md): for each cluster its
// size, mass, shape (gyration.hpp), contacts (contacts.hpp), size and density
// (mass_radius.hpp), fractal dimensions (box_counting.hpp, mass_radius.hpp) and motion
// (cluster_motion.hpp: velocity, spin, kinetic energies); for all
// spheres of the box and for the largest cluster the curves N(eps), P(r), n(r); the mass
// spectrum; and the power laws across the population of clusters (Richardson 1995 §3).
// A pure function of the spheres and the box: state in, numbers out.
#include <cstdint>
#include <optional>
#include <vector>

#include "ballagg/analysis/box_counting.hpp"
#include "ballagg/analysis/cluster_motion.hpp"
#include "ballagg/analysis/cluster_unwrapping.hpp"
#include "ballagg/analysis/gyration.hpp"
#include "ballagg/analysis/linear_fit.hpp"
#include "ballagg/analysis/mass_radius.hpp"
#include "ballagg/analysis/mass_spectrum.hpp"
#include "ballagg/analysis/pair_distribution.hpp"
#include "ballagg/core/box.hpp"
#include "ballagg/core/sphere_table.hpp"

namespace ballagg {

// Clusters smaller than this get no fractal dimension (NaN): a handful of centres spans
// too few box sizes or radii for a slope.
inline constexpr int kFractalMinSize = 10;
// The population fits (R_max and rho against N_a) use the clusters of at least this many
// spheres, and need at least kPopulationMinSizes distinct sizes among them.
inline constexpr int kPopulationMinSize = 2;
inline constexpr int kPopulationMinSizes = 3;

template <int D>
struct ClusterSummary {
  int size = 0;
  double mass = 0.0;
  Vec<D> centre_of_mass = Vec<D>::Zero();  // in the box when periodic
  GyrationShape<D> shape;                  // A_r (4.3), D (4.4), R_g
  double r_max = 0.0, density = 0.0;       // Richardson (7), M / V(R_max)
  double contacts = 0.0;                   // N_c (4.5) over the cluster's own pairs
  // The fractal dimensions, each NaN when withheld, with the reason (fit_flaw.hpp).
  double box_dimension = 0.0, box_dimension_error = 0.0;                  // (4.7) on 3R..min(L/2, 2 R_max)
  double mass_radius_dimension = 0.0, mass_radius_dimension_error = 0.0;  // §3, fitted on 4R..R_g
  double richardson_dimension = 0.0, richardson_dimension_error = 0.0;    // §3, through every centre
  FitFlaw box_dimension_flaw = FitFlaw::none, mass_radius_dimension_flaw = FitFlaw::none,
          richardson_dimension_flaw = FitFlaw::none;
  bool percolating = false;                // wraps around the periodic box
  ClusterMotion<D> motion;                 // velocity, spin, translational and rotational energy
};

// Richardson's "mean value of f_D ... using inverse square weights": the mean of the
// clusters' dimensions weighted by 1 / error^2, and the weighted standard deviation about
// it (his "1.8 +- 0.4"), over the clusters with a dimension and a non-zero error. NaN
// when there are none.
struct WeightedMean {
  int clusters = 0;
  double mean = 0.0, spread = 0.0;
};

// Power laws across clusters: R_max ~ N_a^(slope), rho ~ N_a^gamma, and the dimension
// they imply, f_D = D / (1 - gamma) (Richardson eq. 32, written for any D).
struct PopulationFits {
  int clusters = 0;                     // clusters used
  std::optional<LinearFit> r_max;       // log R_max against log N_a
  std::optional<LinearFit> density;     // log rho against log N_a
  double dimension = 0.0;               // D / (1 - gamma); NaN when withheld
  FitFlaw dimension_flaw = FitFlaw::none;
  WeightedMean mass_radius_dimension;   // of the clusters' mass_radius_dimension
  WeightedMean richardson_dimension;    // of their richardson_dimension
};

template <int D>
struct AggregateAnalysis {
  Box<D> box;
  int n_spheres = 0;
  double length_unit = 0.0;               // R: the mean sphere radius
  double contacts = 0.0;                  // N_c (4.5) over all spheres of the box
  BoxCounting box_counting;               // (4.7) over all centres
  PairDistribution pair_distribution;     // (4.6): all spheres, and the largest cluster
  int largest = 0;                        // index of the largest cluster (lowest on a tie)
  BoxCounting largest_box_counting;
  MassRadius<D> largest_mass_radius;
  std::vector<ClusterSummary<D>> clusters;  // in order of each cluster's first sphere
  std::vector<MassSpectrumBin> mass_spectrum;
  PopulationFits population;
  double mass = 0.0;                        // of all spheres
  double aggregated_mass_fraction = 0.0;    // in clusters of two or more spheres
  double heaviest_mass_fraction = 0.0;      // in the heaviest cluster
  double translational_energy = 0.0, rotational_energy = 0.0;  // sums over the clusters
};

// The spheres of a state file (positions folded into the box when periodic).
template <int D>
AggregateAnalysis<D> analyze_aggregates(const Box<D>& box, const SphereTable<D>& spheres);

// The length unit R of the analysis: the radius when all are equal (the paper's case,
// without the round-off of a mean), otherwise the mean radius.
double length_unit_of(const std::vector<double>& radii);

extern template AggregateAnalysis<2> analyze_aggregates<2>(const Box<2>&, const SphereTable<2>&);
extern template AggregateAnalysis<3> analyze_aggregates<3>(const Box<3>&, const SphereTable<3>&);

}  // namespace ballagg
