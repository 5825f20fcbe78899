#include "ballagg/io/kinetics_files.hpp"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace ballagg {
namespace {

using Json = nlohmann::ordered_json;

Json number(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json decay_json(const DecayFit& d) {
  return Json{{"exponent", number(d.exponent)},
              {"exponent_error", number(d.error)},
              {"points", d.fit ? d.fit->points : 0},
              {"prefactor", d.fit ? number(std::exp(d.fit->intercept)) : Json(nullptr)},
              {"flaw", flaw_code(d.flaw)}};
}

std::string collapse_csv(const std::vector<CollapsePoint>& points) {
  std::string out = "time,size,clusters,mean_size,scaled_size,scaled_count\n";
  for (const CollapsePoint& p : points)
    out += fmt::format("{},{},{},{},{},{}\n", p.time, p.size, p.clusters, p.mean_size, p.scaled_size, p.scaled_count);
  return out;
}

}  // namespace

std::map<std::string, std::string> kinetics_files(const Kinetics& k, int dimension, const std::string& series_file,
                                                  const std::vector<CollapsePoint>& collapse) {
  Json j;
  j["time_series"] = series_file;
  j["window"] = Json{{"start", number(k.window_start)},
                     {"end", number(k.window_end)},
                     {"automatic", k.automatic_window},
                     {"rule", fmt::format("from n <= {} n(0) to the last n >= {}, {} log-spaced samples",
                                          kKineticsStartFraction, kKineticsEndClusters, kKineticsSamples)}};
  j["clusters_decay_z"] = decay_json(k.clusters);
  j["energy_decay_theta"] = decay_json(k.energy);
  j["mean_field"] = Json{{"z_coalescing_spheres", mean_field_z(dimension, dimension)},
                         {"z_of_fractal_dimension", "1 / (3/2 - (d - 1) / d_f)"},
                         {"theta", "= z"}};
  j["errors"] = "standard errors of the least-squares slope; successive samples are correlated, so the spread "
                "over realizations (ballagg sweep) is the error to quote";
  std::map<std::string, std::string> files{{"kinetics.json", j.dump(2) + "\n"}};
  if (!collapse.empty()) files["kinetics_collapse.csv"] = collapse_csv(collapse);
  return files;
}

}  // namespace ballagg
