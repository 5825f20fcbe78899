#include "end_of_run_report.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <fmt/format.h>

namespace ballagg::cli {
namespace {

using Json = nlohmann::json;

// A number of a JSON object, or NaN when it is missing or null (an undefined quantity).
double number(const Json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::numeric_limits<double>::quiet_NaN();
}

std::string text(const Json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string("?");
}

// The setting or condition behind each stop reason (docs/outputs.md, summary.json).
std::string stop_cause(const std::string& reason) {
  if (reason == "clusters") return "stop.clusters";
  if (reason == "time") return "stop.time";
  if (reason == "wall_seconds") return "stop.wall_seconds";
  if (reason == "output_limit") return "the output limit";
  if (reason == "no_more_events") return "no more events";
  if (reason == "no_collision_possible") return "no collision possible";
  if (reason == "aggregated") return "stop.aggregated_fraction";
  if (reason == "body_spans_box") return "a body spanning the box";
  return reason;
}

// "1.82 ± 0.03", "1.82", or "withheld (FLAW)".
std::string value_with_error(const Json& j, const char* key, const char* error_key, const char* flaw_key) {
  const double v = number(j, key), e = number(j, error_key);
  if (std::isnan(v)) return fmt::format("withheld ({})", j.contains(flaw_key) ? text(j, flaw_key) : "no fit");
  return std::isnan(e) ? fmt::format("{:.3f}", v) : fmt::format("{:.3f} ± {:.3f}", v, e);
}

}  // namespace

std::string run_report(const Json& s) {
  const bool steps = s.contains("steps");
  const double count = number(s, steps ? "steps" : "events"), seconds = number(s, "wall_seconds");
  std::string out = fmt::format("Loop: {}, {}D, {} spheres; stopped by {} at t = {:.6g} after {:.0f} {} in {:.3g} s ({:.3g} {}/s)\n",
                                text(s, "engine"), s.value("dimension", 0), s.value("n_particles", 0),
                                stop_cause(text(s, "stop_reason")), number(s, "time"), count, steps ? "steps" : "events",
                                seconds, seconds > 0.0 ? count / seconds : 0.0, steps ? "steps" : "events");
  const double ke0 = number(s, "kinetic_energy_initial"), ke = number(s, "kinetic_energy_final");
  const int clusters = s.value("n_clusters", 0);
  out += fmt::format("Final: {} cluster{} (largest {}), kinetic energy {:.6g} ({:.3g} of the initial), largest overlap {}\n",
                     clusters, clusters == 1 ? "" : "s", s.value("largest_cluster", 0), ke, ke0 > 0.0 ? ke / ke0 : 0.0,
                     std::isnan(number(s, "max_overlap")) ? std::string("none (no spheres near each other)")
                                                           : fmt::format("{:.3g} of the contact distance", number(s, "max_overlap")));
  return out;
}

std::string analysis_headline(const Json& a) {
  const Json& all = a.at("all_spheres");
  const Json& box = all.at("box_counting");
  const Json& largest = a.at("largest_cluster");
  std::string out = fmt::format("D_f = {} (box counting over all spheres, {} levels), N_c = {:.4f}\n",
                                value_with_error(box, "dimension", "dimension_error", "flaw"),
                                box.value("levels_fitted", 0), number(all, "contacts"));
  out += fmt::format("largest cluster: {} spheres, A_r = {:.3g}, R_g = {:.4g}, f_D = {} (mass-radius, 4R..R_g)\n",
                     largest.value("size", 0), number(largest, "aspect_ratio"), number(largest, "radius_of_gyration"),
                     value_with_error(largest, "mass_radius_dimension", "mass_radius_dimension_error",
                                      "mass_radius_dimension_flaw"));
  return out;
}

namespace {

// A JSON file of the given directory, or null when it cannot be read or parsed.
Json json_of(const std::string& dir, const char* name) {
  std::ifstream in(std::filesystem::path(dir) / name);
  if (!in) return nullptr;
  return Json::parse(in, nullptr, false);
}

}  // namespace

std::string run_report_of(const std::string& run_dir) {
  const Json s = json_of(run_dir, "summary.json");
  return s.is_object() ? run_report(s) : std::string();
}

std::string kinetics_headline_of(const std::string& dir) {
  const Json k = json_of(dir, "kinetics.json");
  if (!k.is_object() || !k.contains("clusters_decay_z") || !k.contains("window")) return {};
  const Json& w = k["window"];
  return fmt::format("z = {} (n ~ t^-z), theta = {} (E ~ t^-theta), over t = {:.4g} .. {:.4g} ({}); mean field for "
                     "coalescing spheres z = theta = {:.3g}\n",
                     value_with_error(k["clusters_decay_z"], "exponent", "exponent_error", "flaw"),
                     value_with_error(k["energy_decay_theta"], "exponent", "exponent_error", "flaw"),
                     number(w, "start"), number(w, "end"), w.value("automatic", false) ? "automatic window" : "--window",
                     number(k["mean_field"], "z_coalescing_spheres"));
}

std::string analysis_headline_of(const std::string& analysis_dir) {
  const Json a = json_of(analysis_dir, "analysis.json");
  if (!a.is_object() || !a.contains("all_spheres") || !a.contains("largest_cluster")) return {};
  return analysis_headline(a);
}

}  // namespace ballagg::cli
