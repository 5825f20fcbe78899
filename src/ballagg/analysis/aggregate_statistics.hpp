#pragma once
// Statistics of the aggregates at the end of a run (Richardson 1995 §3, Figs. 6, 8, 10,
// 11b): mass spectrum, kinetic energy and spin against mass, R_max (7) against the number
// of spheres N_a with its power-law exponent, the mass-radius fractal dimension of each
// aggregate and their inverse-square-weighted mean, the spherically averaged density
// rho = M / (volume of the ball of radius R_max) with its exponent gamma, and
// f_D = D / (1 - gamma) (eq. 32 for D = 3).
//
// Works on any state, e.g. one read back from final.csv (spins from its wx, wy, wz
// columns, zero if there are none); clusters are the aggregates.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ballagg/core/state.hpp"

namespace ballagg {

// Aggregates with fewer spheres than this get no fractal dimension (a slope through two
// distances means nothing).
inline constexpr int kMinSpheresForFractalDimension = 4;

struct PowerLawFit {
  double exponent = 0.0;  // least-squares slope on log-log axes
  double error = 0.0;     // its standard error
  double prefactor = 0.0;
  int points = 0;
};

struct BodyStatistics {
  int spheres = 0;
  double mass = 0.0;
  double r_max = 0.0;                  // eq. (7)
  double translational_energy = 0.0;
  double rotational_energy = 0.0;      // eq. (2)
  double spin = 0.0;                   // |omega|
  double density = 0.0;                // M / (volume of the ball of radius R_max)
  double fractal_dimension = 0.0;      // mass-radius slope; 0 when not defined
  double fractal_error = 0.0;
};

struct AggregateStatistics {
  std::vector<BodyStatistics> bodies;  // one per cluster, by decreasing mass
  std::vector<std::pair<double, int>> mass_spectrum;  // (mass, number of bodies), by mass
  double aggregated_fraction = 0.0;    // of the mass in bodies of two or more spheres
  double largest_mass_fraction = 0.0;
  PowerLawFit r_max;                   // R_max ~ N_a^exponent over bodies with N_a >= 2
  PowerLawFit density;                 // rho ~ N_a^gamma over bodies with N_a >= 2
  double fractal_from_density = 0.0;   // D / (1 - gamma)
  double mean_fractal_dimension = 0.0;  // inverse-square-weighted mean over the aggregates
  double fractal_dimension_spread = 0.0;  // weighted standard deviation
  int fractal_dimension_bodies = 0;
};

template <int D>
AggregateStatistics aggregate_statistics(const State<D>& s);

// Least-squares fit of log y = log prefactor + exponent log x.
PowerLawFit fit_power_law(const std::vector<double>& x, const std::vector<double>& y);

// aggregates.csv: one row per body; mass_spectrum.csv; and the summary as JSON.
std::string aggregates_csv(const AggregateStatistics& a);
std::string mass_spectrum_csv(const AggregateStatistics& a);
nlohmann::ordered_json aggregate_summary_json(const AggregateStatistics& a);

}  // namespace ballagg
