#include "ballagg/analysis/aggregate_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <fmt/format.h>

#include "ballagg/engines/rigid_body/inertia.hpp"

namespace ballagg {

PowerLawFit fit_power_law(const std::vector<double>& x, const std::vector<double>& y) {
  PowerLawFit f;
  f.points = static_cast<int>(x.size());
  if (f.points < 2) return f;
  double mx = 0.0, my = 0.0;
  for (int k = 0; k < f.points; ++k) {
    mx += std::log(x[k]);
    my += std::log(y[k]);
  }
  mx /= f.points;
  my /= f.points;
  double sxx = 0.0, sxy = 0.0;
  for (int k = 0; k < f.points; ++k) {
    const double dx = std::log(x[k]) - mx;
    sxx += dx * dx;
    sxy += dx * (std::log(y[k]) - my);
  }
  if (sxx == 0.0) return f;
  f.exponent = sxy / sxx;
  f.prefactor = std::exp(my - f.exponent * mx);
  if (f.points > 2) {
    double residual = 0.0;
    for (int k = 0; k < f.points; ++k) {
      const double e = std::log(y[k]) - (my + f.exponent * (std::log(x[k]) - mx));
      residual += e * e;
    }
    f.error = std::sqrt(residual / (f.points - 2) / sxx);
  }
  return f;
}

namespace {

// The mass-radius fractal dimension: slope of log(enclosed mass) against log(distance of
// the sphere centres from the centre of mass), with its standard error.
PowerLawFit mass_radius_fit(std::vector<std::pair<double, double>> distance_mass) {
  std::sort(distance_mass.begin(), distance_mass.end());
  std::vector<double> r, m;
  double enclosed = 0.0;
  for (const auto& [distance, mass] : distance_mass) {
    enclosed += mass;
    if (distance <= 0.0) continue;
    r.push_back(distance);
    m.push_back(enclosed);
  }
  return fit_power_law(r, m);
}

}  // namespace

template <int D>
AggregateStatistics aggregate_statistics(const State<D>& s) {
  AggregateStatistics a;
  std::map<double, int> spectrum;
  double total = 0.0, aggregated = 0.0;
  std::vector<Vec<D>> x;
  std::vector<double> radius, mass;
  for (int c : s.alive_clusters()) {
    const Cluster<D>& k = s.clusters[c];
    x.clear(), radius.clear(), mass.clear();
    for (int i : k.members) {
      x.push_back(s.unwrapped_position(i, s.time));
      radius.push_back(s.spheres.radius[i]);
      mass.push_back(s.spheres.mass[i]);
    }
    const MassProperties<D> p = sphere_mass_properties<D>(x, radius, mass);
    BodyStatistics b;
    b.spheres = k.size();
    b.mass = k.mass;
    std::vector<std::pair<double, double>> distance_mass;
    for (std::size_t m = 0; m < x.size(); ++m) {
      const double r = (x[m] - p.centre).norm();
      b.r_max = std::max(b.r_max, r + radius[m]);
      distance_mass.push_back({r, mass[m]});
    }
    b.translational_energy = 0.5 * k.mass * k.velocity.squaredNorm();
    if (!s.spin.empty()) {
      const Spin<D>& w = s.spin[c].angular_velocity;
      b.rotational_energy = 0.5 * w.dot(p.inertia * w);
      b.spin = w.norm();
    }
    const double ball = D == 2 ? std::numbers::pi * b.r_max * b.r_max : 4.0 / 3.0 * std::numbers::pi * std::pow(b.r_max, 3);
    b.density = b.mass / ball;
    if (b.spheres >= kMinSpheresForFractalDimension) {
      const PowerLawFit f = mass_radius_fit(std::move(distance_mass));
      b.fractal_dimension = f.exponent;
      b.fractal_error = f.error;
    }
    a.bodies.push_back(b);
    ++spectrum[b.mass];
    total += b.mass;
    if (b.spheres > 1) aggregated += b.mass;
  }
  std::sort(a.bodies.begin(), a.bodies.end(), [](const BodyStatistics& p, const BodyStatistics& q) {
    return p.mass > q.mass || (p.mass == q.mass && p.spheres > q.spheres);
  });
  a.mass_spectrum.assign(spectrum.begin(), spectrum.end());
  a.aggregated_fraction = total > 0.0 ? aggregated / total : 0.0;
  a.largest_mass_fraction = !a.bodies.empty() && total > 0.0 ? a.bodies.front().mass / total : 0.0;

  std::vector<double> n, r_max, density;
  double weight = 0.0, weighted = 0.0, weighted_square = 0.0;
  for (const BodyStatistics& b : a.bodies) {
    if (b.spheres < 2) continue;
    n.push_back(b.spheres);
    r_max.push_back(b.r_max);
    density.push_back(b.density);
    if (b.fractal_error > 0.0) {
      const double w = 1.0 / (b.fractal_error * b.fractal_error);
      weight += w;
      weighted += w * b.fractal_dimension;
      weighted_square += w * b.fractal_dimension * b.fractal_dimension;
      ++a.fractal_dimension_bodies;
    }
  }
  a.r_max = fit_power_law(n, r_max);
  a.density = fit_power_law(n, density);
  if (a.density.points >= 2 && a.density.exponent < 1.0) a.fractal_from_density = D / (1.0 - a.density.exponent);
  if (weight > 0.0) {
    a.mean_fractal_dimension = weighted / weight;
    a.fractal_dimension_spread =
        std::sqrt(std::max(0.0, weighted_square / weight - a.mean_fractal_dimension * a.mean_fractal_dimension));
  }
  return a;
}

std::string aggregates_csv(const AggregateStatistics& a) {
  std::string out =
      "spheres,mass,r_max,translational_energy,rotational_energy,spin,density,fractal_dimension,fractal_error\n";
  for (const BodyStatistics& b : a.bodies)
    out += fmt::format("{},{},{},{},{},{},{},{},{}\n", b.spheres, b.mass, b.r_max, b.translational_energy,
                       b.rotational_energy, b.spin, b.density, b.fractal_dimension, b.fractal_error);
  return out;
}

std::string mass_spectrum_csv(const AggregateStatistics& a) {
  std::string out = "mass,bodies\n";
  for (const auto& [mass, count] : a.mass_spectrum) out += fmt::format("{},{}\n", mass, count);
  return out;
}

nlohmann::ordered_json aggregate_summary_json(const AggregateStatistics& a) {
  nlohmann::ordered_json j;
  j["bodies"] = a.bodies.size();
  j["aggregated_fraction"] = a.aggregated_fraction;
  j["largest_mass_fraction"] = a.largest_mass_fraction;
  auto fit = [](const PowerLawFit& f) {
    return nlohmann::ordered_json{{"exponent", f.exponent}, {"error", f.error}, {"prefactor", f.prefactor}, {"points", f.points}};
  };
  j["r_max_vs_spheres"] = fit(a.r_max);
  j["density_vs_spheres"] = fit(a.density);
  j["fractal_dimension_from_density"] = a.fractal_from_density;
  j["mean_fractal_dimension"] = a.mean_fractal_dimension;
  j["fractal_dimension_spread"] = a.fractal_dimension_spread;
  j["fractal_dimension_bodies"] = a.fractal_dimension_bodies;
  return j;
}

template AggregateStatistics aggregate_statistics<2>(const State<2>&);
template AggregateStatistics aggregate_statistics<3>(const State<3>&);

}  // namespace ballagg
