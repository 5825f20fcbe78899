#pragma once
// The kinetic scaling laws of ballistic aggregation (Carnevale, Pomeau & Young 1990; Trizac
// & Hansen 1995): the number of clusters n(t) ~ t^-z and the kinetic energy E(t) ~ t^-theta,
// fitted by least squares of log n and log E against log t over a window of time, and the
// scaling form of the size distribution, n_k(t) = S(t)^-2 f(k / S(t)) with S the mean size.
// A pure function of a run's time series (and of its frames' mass spectra).
#include <optional>
#include <utility>
#include <vector>

#include "ballagg/analysis/fit_flaw.hpp"
#include "ballagg/analysis/linear_fit.hpp"
#include "ballagg/analysis/mass_spectrum.hpp"

namespace ballagg {

// The automatic window opens once the clusters have fallen to this fraction of their
// initial number (the mean cluster holds ten spheres: the early, ballistic regime of
// monomers meeting monomers is over)...
inline constexpr double kKineticsStartFraction = 0.1;
// ... and closes before fewer than this many clusters are left (the finite box then
// dominates, and the counts are too few to average).
inline constexpr double kKineticsEndClusters = 20.0;
// The window is sampled at this many logarithmically spaced times (the time series is
// dense where clusters merge fast; equal weight per decade of time instead).
inline constexpr int kKineticsSamples = 40;

// Mean field (momentum conservation, v ~ M^-1/2; cross-section ~ R^(d-1), R ~ M^(1/d_f)):
// a kernel of homogeneity lambda = (d - 1)/d_f - 1/2 and z = 1 / (1 - lambda); coalescing
// spheres (d_f = d) give z = 2d/(d+2), 1 in 2D and 6/5 in 3D. The energy per cluster stays
// of order one (M v^2 ~ 1), so theta = z.
constexpr double mean_field_z(int dimension, double fractal_dimension) {
  return 1.0 / (1.0 - ((dimension - 1.0) / fractal_dimension - 0.5));
}

struct KineticSeries {
  std::vector<double> time, clusters, energy;  // rows of timeseries.csv, time ascending
};

// slope of log y against log t is -exponent; NaN exponent with a flaw when withheld.
struct DecayFit {
  double exponent = 0.0, error = 0.0;
  std::optional<LinearFit> fit;
  FitFlaw flaw = FitFlaw::none;
};

struct Kinetics {
  double window_start = 0.0, window_end = 0.0;
  bool automatic_window = true;
  DecayFit clusters;  // z
  DecayFit energy;    // theta
};

// window: [t0, t1] given by the user, or the automatic one when nullopt.
Kinetics fit_kinetics(const KineticSeries& series, std::optional<std::pair<double, double>> window);

// One point of the scaling collapse of a frame's size distribution: x = k / S(t) and
// y = S(t)^2 n_k / N, with n_k the clusters of size k and N the spheres.
struct CollapsePoint {
  double time = 0.0;
  int size = 0;
  long long clusters = 0;
  double mean_size = 0.0, scaled_size = 0.0, scaled_count = 0.0;
};

std::vector<CollapsePoint> scaling_collapse(double time, const std::vector<MassSpectrumBin>& spectrum);

}  // namespace ballagg
