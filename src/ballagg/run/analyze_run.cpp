#include "ballagg/run/analyze_run.hpp"

#include <filesystem>
#include <map>

#include <fmt/format.h>

#include "ballagg/analysis/aggregate_analysis.hpp"
#include "ballagg/config/config.hpp"
#include "ballagg/io/analysis_files.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/state_csv.hpp"

namespace ballagg {
namespace {

namespace fs = std::filesystem;

template <int D>
std::string analyze_in_dimension(const Config& config, const std::string& state_file, const std::string& out_dir) {
  const Box<D> box{resolved_box_length(config), config.system.boundary};
  const SphereTable<D> spheres = read_state_csv<D>(state_file);
  for (std::size_t i = 0; i < spheres.position.size(); ++i) {
    for (int a = 0; a < D; ++a) {
      const double x = spheres.position[i][a];
      // Folded centres lie in [0, L); with walls a centre lies at least one radius inside.
      if (x < 0.0 || x > box.length)
        throw InputError(fmt::format("{}:{}: centre outside the box [0, {}] of {} (is this the right configuration?)",
                                     state_file, spheres.line[i], box.length, config.source));
    }
  }
  const AggregateAnalysis<D> analysis = analyze_aggregates(box, spheres);
  prepare_output_dir(out_dir);
  const std::map<std::string, std::string> files = analysis_files(analysis, state_file);
  for (const auto& [name, content] : files)
    if (name != "analysis.json") write_file_atomically(out_dir, name, content);
  // analysis.json last: when it exists, the tables it lists are complete.
  write_file_atomically(out_dir, "analysis.json", files.at("analysis.json"));
  return out_dir;
}

}  // namespace

std::string analyze_run(const AnalyzeRequest& r) {
  if (r.run_dir.empty() && (r.state_file.empty() || r.config_file.empty()))
    throw InputError("analyze: give a run directory, or both --state and --config");
  if (!r.run_dir.empty() && !fs::is_directory(r.run_dir))
    throw InputError(fmt::format("{}: not a run directory (expected config.toml and final.csv in it)", r.run_dir));
  const std::string config_file = !r.config_file.empty() ? r.config_file : (fs::path(r.run_dir) / "config.toml").string();
  const std::string state_file = !r.state_file.empty() ? r.state_file : (fs::path(r.run_dir) / "final.csv").string();
  fs::path out_dir = r.out_dir;
  if (out_dir.empty()) out_dir = !r.run_dir.empty() ? fs::path(r.run_dir) : fs::path(state_file).parent_path();
  if (out_dir.empty()) out_dir = fs::current_path();
  const Config config = load_config(config_file, {});
  if (config.system.dimension == 2) return analyze_in_dimension<2>(config, state_file, out_dir.string());
  return analyze_in_dimension<3>(config, state_file, out_dir.string());
}

}  // namespace ballagg
