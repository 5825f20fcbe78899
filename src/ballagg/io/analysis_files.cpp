#include "ballagg/io/analysis_files.hpp"

#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "ballagg/analysis/contacts.hpp"

namespace ballagg {
namespace {

using Json = nlohmann::ordered_json;

// NaN and infinities have no JSON number: null.
Json number(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

template <int N>
Json vector_json(const Eigen::Matrix<double, N, 1>& v) {
  Json a = Json::array();
  for (int k = 0; k < N; ++k) a.push_back(number(v[k]));
  return a;
}

Json fit_json(const std::optional<LinearFit>& f) {
  if (!f) return nullptr;
  return Json{{"slope", number(f->slope)},
              {"slope_error", number(f->slope_error)},
              {"intercept", number(f->intercept)},
              {"intercept_error", number(f->intercept_error)},
              {"points", f->points}};
}

// Every flaw's code with its sentence, so that analysis.json explains its own codes.
Json flaw_definitions() {
  Json d = Json::object();
  for (FitFlaw f : {FitFlaw::none, FitFlaw::cluster_too_small, FitFlaw::too_few_points, FitFlaw::hole_at_centre,
                    FitFlaw::outside_dimension_range})
    d[flaw_code(f)] = flaw_explanation(f);
  return d;
}

Json weighted_mean_json(const WeightedMean& m) {
  return Json{{"mean", number(m.mean)}, {"spread", number(m.spread)}, {"clusters", m.clusters}};
}

Json box_counting_json(const BoxCounting& b) {
  int fitted = 0;
  for (char f : b.fitted) fitted += f;
  return Json{{"dimension", number(b.dimension)},
              {"dimension_error", number(b.dimension_error)},
              {"prefactor", number(b.prefactor)},
              {"prefactor_error", number(b.prefactor_error)},
              {"levels_fitted", fitted},
              {"flaw", flaw_code(b.flaw)}};
}

template <int D>
Json cluster_json(const ClusterSummary<D>& c) {
  Json eigenvalues = Json::array();
  for (double l : c.shape.eigenvalues) eigenvalues.push_back(number(l));
  return Json{{"size", c.size},
              {"mass", number(c.mass)},
              {"centre_of_mass", vector_json<D>(c.centre_of_mass)},
              {"radius_of_gyration", number(c.shape.radius_of_gyration)},
              {"r_max", number(c.r_max)},
              {"density", number(c.density)},
              {"aspect_ratio", number(c.shape.aspect_ratio)},
              {"gyration_eigenvalues", eigenvalues},
              {"orientation", vector_json<D>(c.shape.orientation())},
              {"contacts", number(c.contacts)},
              {"contacts_with_self", number(relative_contacts_with_self<D>(c.contacts))},
              {"box_counting_dimension", number(c.box_dimension)},
              {"box_counting_dimension_error", number(c.box_dimension_error)},
              {"box_counting_dimension_flaw", flaw_code(c.box_dimension_flaw)},
              {"mass_radius_dimension", number(c.mass_radius_dimension)},
              {"mass_radius_dimension_error", number(c.mass_radius_dimension_error)},
              {"mass_radius_dimension_flaw", flaw_code(c.mass_radius_dimension_flaw)},
              {"richardson_dimension", number(c.richardson_dimension)},
              {"richardson_dimension_error", number(c.richardson_dimension_error)},
              {"richardson_dimension_flaw", flaw_code(c.richardson_dimension_flaw)},
              {"percolating", c.percolating},
              {"velocity", vector_json<D>(c.motion.velocity)},
              {"angular_velocity", vector_json<kSpinDim<D>>(c.motion.angular_velocity)},
              {"spin", number(c.motion.spin())},
              {"translational_energy", number(c.motion.translational_energy)},
              {"rotational_energy", number(c.motion.rotational_energy)}};
}

std::string num(double v) { return fmt::format("{}", v); }

template <int D>
std::string clusters_csv(const AggregateAnalysis<D>& a) {
  static constexpr const char* axes[] = {"x", "y", "z"};
  fmt::memory_buffer out;
  auto put = [&](const auto&... parts) { (fmt::format_to(std::back_inserter(out), "{}", parts), ...); };
  put("cluster,size,mass");
  for (int k = 0; k < D; ++k) put(",com_", axes[k]);
  put(",radius_of_gyration,r_max,density,aspect_ratio");
  for (int k = 0; k < D; ++k) put(",lambda_", k + 1);
  for (int k = 0; k < D; ++k) put(",orientation_", axes[k]);
  put(",contacts,box_counting_dimension,box_counting_dimension_error,box_counting_dimension_flaw,"
      "mass_radius_dimension,mass_radius_dimension_error,mass_radius_dimension_flaw,richardson_dimension,"
      "richardson_dimension_error,richardson_dimension_flaw,percolating");
  for (int k = 0; k < D; ++k) put(",velocity_", axes[k]);
  for (int k = 3 - kSpinDim<D>; k < 3; ++k) put(",omega_", axes[k]);  // 2D: omega_z only
  put(",spin,translational_energy,rotational_energy\n");
  for (std::size_t c = 0; c < a.clusters.size(); ++c) {
    const ClusterSummary<D>& s = a.clusters[c];
    put(c, ",", s.size, ",", num(s.mass));
    for (int k = 0; k < D; ++k) put(",", num(s.centre_of_mass[k]));
    put(",", num(s.shape.radius_of_gyration), ",", num(s.r_max), ",", num(s.density), ",", num(s.shape.aspect_ratio));
    for (int k = 0; k < D; ++k) put(",", num(s.shape.eigenvalues[k]));
    for (int k = 0; k < D; ++k) put(",", num(s.shape.orientation()[k]));
    put(",", num(s.contacts), ",", num(s.box_dimension), ",", num(s.box_dimension_error), ",",
        flaw_code(s.box_dimension_flaw), ",", num(s.mass_radius_dimension), ",", num(s.mass_radius_dimension_error),
        ",", flaw_code(s.mass_radius_dimension_flaw), ",", num(s.richardson_dimension), ",",
        num(s.richardson_dimension_error), ",", flaw_code(s.richardson_dimension_flaw), ",", s.percolating ? 1 : 0);
    for (int k = 0; k < D; ++k) put(",", num(s.motion.velocity[k]));
    for (int k = 0; k < kSpinDim<D>; ++k) put(",", num(s.motion.angular_velocity[k]));
    put(",", num(s.motion.spin()), ",", num(s.motion.translational_energy), ",", num(s.motion.rotational_energy), "\n");
  }
  return fmt::to_string(out);
}

template <int D>
std::string box_counting_csv(const AggregateAnalysis<D>& a) {
  std::string out = "level,eps,boxes_all,boxes_largest,fitted\n";
  const BoxCounting& b = a.box_counting;
  for (std::size_t k = 0; k < b.level.size(); ++k)
    out += fmt::format("{},{},{},{},{}\n", b.level[k], b.eps[k], b.boxes[k], a.largest_box_counting.boxes[k],
                       b.fitted[k] ? 1 : 0);
  return out;
}

template <int D>
std::string pair_distribution_csv(const AggregateAnalysis<D>& a) {
  std::string out = "r,r_over_R,P_all,P_largest\n";
  const PairDistribution& p = a.pair_distribution;
  for (std::size_t k = 0; k < p.r.size(); ++k)
    out += fmt::format("{},{},{},{}\n", p.r[k], p.r[k] / a.length_unit, p.all[k], p.cluster[k]);
  return out;
}

template <int D>
std::string mass_radius_csv(const AggregateAnalysis<D>& a) {
  std::string out = "r,r_over_R,enclosed,fitted\n";
  const MassRadius<D>& m = a.largest_mass_radius;
  for (std::size_t k = 0; k < m.radius.size(); ++k)
    out += fmt::format("{},{},{},{}\n", m.radius[k], m.radius[k] / a.length_unit, m.enclosed[k], m.fitted[k] ? 1 : 0);
  return out;
}

std::string mass_spectrum_csv(const std::vector<MassSpectrumBin>& bins) {
  std::string out = "size,mass,clusters\n";
  for (const MassSpectrumBin& b : bins) out += fmt::format("{},{},{}\n", b.size, b.mass, b.clusters);
  return out;
}

}  // namespace

template <int D>
std::map<std::string, std::string> analysis_files(const AggregateAnalysis<D>& a, const std::string& state_file) {
  Json j;
  j["state_file"] = state_file;
  j["dimension"] = D;
  j["n_spheres"] = a.n_spheres;
  j["n_clusters"] = a.clusters.size();
  j["box_length"] = a.box.length;
  j["boundary"] = to_string(a.box.boundary);
  j["length_unit"] = a.length_unit;
  j["mass"] = a.mass;
  j["aggregated_mass_fraction"] = number(a.aggregated_mass_fraction);
  j["heaviest_mass_fraction"] = number(a.heaviest_mass_fraction);
  j["translational_energy"] = a.translational_energy;
  j["rotational_energy"] = a.rotational_energy;
  j["definitions"] = Json{{"contact_factor_alpha_R", kContactFactor},
                          {"max_contacts_N_max", kMaxContacts<D>},
                          {"pair_distribution_r_over_R", {kPairDistributionMin, kPairDistributionMax}},
                          {"box_counting_eps_range", {fmt::format("{} R", kBoxCountingSmallest), "L/2"}},
                          {"mass_radius_r_range", {fmt::format("{} R", kMassRadiusInner), "R_g"}},
                          {"fractal_min_size", kFractalMinSize},
                          {"richardson_min_size", kRichardsonMinSize},
                          {"fit_min_points", kMinFitPoints},
                          {"dimension_excess", kDimensionExcess},
                          {"fit_flaws", flaw_definitions()}};
  j["all_spheres"] = Json{{"contacts", number(a.contacts)},
                          {"contacts_with_self", number(relative_contacts_with_self<D>(a.contacts))},
                          {"box_counting", box_counting_json(a.box_counting)},
                          {"correlation_dimension", number(a.pair_distribution.all_dimension)},
                          {"correlation_dimension_flaw", flaw_code(a.pair_distribution.all_flaw)},
                          {"correlation_fit", fit_json(a.pair_distribution.all_fit)}};
  Json largest = cluster_json(a.clusters[a.largest]);
  largest["cluster"] = a.largest;
  largest["box_counting"] = box_counting_json(a.largest_box_counting);
  largest["mass_radius_fit"] = fit_json(a.largest_mass_radius.fit);
  largest["correlation_dimension"] = number(a.pair_distribution.cluster_dimension);
  largest["correlation_dimension_flaw"] = flaw_code(a.pair_distribution.cluster_flaw);
  largest["nearest_centre_to_centre_of_mass"] = number(a.largest_mass_radius.nearest_centre);
  largest["correlation_fit"] = fit_json(a.pair_distribution.cluster_fit);
  j["largest_cluster"] = largest;
  j["population"] = Json{{"clusters_used", a.population.clusters},
                         {"min_size", kPopulationMinSize},
                         {"r_max_vs_size", fit_json(a.population.r_max)},
                         {"density_vs_size", fit_json(a.population.density)},
                         {"dimension_from_density", number(a.population.dimension)},
                         {"dimension_from_density_flaw", flaw_code(a.population.dimension_flaw)},
                         {"mean_mass_radius_dimension", weighted_mean_json(a.population.mass_radius_dimension)},
                         {"mean_richardson_dimension", weighted_mean_json(a.population.richardson_dimension)}};
  j["files"] = {"clusters.csv", "mass_spectrum.csv", "box_counting.csv", "pair_distribution.csv", "mass_radius.csv"};
  return {{"analysis.json", j.dump(2) + "\n"},
          {"clusters.csv", clusters_csv(a)},
          {"mass_spectrum.csv", mass_spectrum_csv(a.mass_spectrum)},
          {"box_counting.csv", box_counting_csv(a)},
          {"pair_distribution.csv", pair_distribution_csv(a)},
          {"mass_radius.csv", mass_radius_csv(a)}};
}

template std::map<std::string, std::string> analysis_files<2>(const AggregateAnalysis<2>&, const std::string&);
template std::map<std::string, std::string> analysis_files<3>(const AggregateAnalysis<3>&, const std::string&);

}  // namespace ballagg
