#include "ballagg/run/analyze_run.hpp"

#include <filesystem>
#include <map>

#include <fmt/format.h>

#include "ballagg/analysis/aggregate_analysis.hpp"
#include "ballagg/config/config.hpp"
#include "ballagg/io/analysis_files.hpp"
#include "ballagg/io/directory_lock.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/run/run_directory.hpp"

namespace ballagg {
namespace {

namespace fs = std::filesystem;

template <int D>
std::string analyze_in_dimension(const Config& config, const std::string& state_file, const std::string& out_dir) {
  const Box<D> box{resolved_box_length(config), config.system.boundary};
  const SphereTable<D> spheres = read_state_in_box<D>(state_file, config);
  prepare_output_dir(out_dir);
  const DirectoryLock lock(out_dir);  // not while a run writes there
  write_analysis(box, spheres, state_file, out_dir);
  return out_dir;
}

}  // namespace

template <int D>
void write_analysis(const Box<D>& box, const SphereTable<D>& spheres, const std::string& state_file,
                    const std::string& out_dir) {
  const std::map<std::string, std::string> files = analysis_files(analyze_aggregates(box, spheres), state_file);
  for (const auto& [name, content] : files)
    if (name != "analysis.json") write_file_atomically(out_dir, name, content);
  // analysis.json last: when it exists, the tables it lists are complete.
  write_file_atomically(out_dir, "analysis.json", files.at("analysis.json"));
}

std::string analyze_run(const AnalyzeRequest& r) {
  if (r.run_dir.empty() && (r.state_file.empty() || r.config_file.empty()))
    throw InputError("analyze: give a run directory, or both --state and --config");
  Config config;
  std::string state_file = r.state_file;
  fs::path out_dir = r.out_dir;
  if (!r.run_dir.empty()) {
    const RunDirectory run = open_run_directory(r.run_dir);
    config = r.config_file.empty() ? run.config : load_config(r.config_file, {});
    if (state_file.empty()) state_file = run.path("final.csv");
    if (out_dir.empty()) out_dir = run.dir;
  } else {
    config = load_config(r.config_file, {});
    if (out_dir.empty()) out_dir = fs::path(state_file).parent_path();
    if (out_dir.empty()) out_dir = fs::current_path();
  }
  if (config.system.dimension == 2) return analyze_in_dimension<2>(config, state_file, out_dir.string());
  return analyze_in_dimension<3>(config, state_file, out_dir.string());
}

template void write_analysis<2>(const Box<2>&, const SphereTable<2>&, const std::string&, const std::string&);
template void write_analysis<3>(const Box<3>&, const SphereTable<3>&, const std::string&, const std::string&);

}  // namespace ballagg
