#include "ballagg/run/run_directory.hpp"

#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "ballagg/config/text_file.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/io/state_csv.hpp"

namespace fs = std::filesystem;

namespace ballagg {

std::string RunDirectory::path(const std::string& name) const { return (fs::path(dir) / name).string(); }

RunDirectory open_run_directory(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(fmt::format("{}: not a run directory (no such directory; give the --out of a ballagg run)", dir));
  RunDirectory run;
  run.dir = dir;
  if (!fs::is_regular_file(run.path("config.toml"), ec))
    throw InputError(fmt::format("{}: not a run directory (no config.toml; give the --out of a ballagg run)", dir));
  run.config = load_config(run.path("config.toml"), {});
  const std::string summary_path = run.path("summary.json");
  const std::string text = read_text_file(summary_path, "run summary", kMaxSettingsFileBytes);
  const nlohmann::json summary = nlohmann::json::parse(text, nullptr, false);
  if (summary.is_discarded() || !summary.contains("time") || !summary["time"].is_number())
    throw InputError(fmt::format("{}: not a ballagg summary (no \"time\")", summary_path));
  run.final_time = summary["time"].get<double>();
  return run;
}

template <int D>
SphereTable<D> read_state_in_box(const std::string& state_file, const Config& config) {
  SphereTable<D> spheres = read_state_csv<D>(state_file);
  const double length = resolved_box_length(config);
  for (std::size_t i = 0; i < spheres.position.size(); ++i) {
    for (int a = 0; a < D; ++a) {
      const double x = spheres.position[i][a];
      // Folded centres lie in [0, L); with walls a centre lies at least one radius inside.
      if (x < 0.0 || x > length)
        throw InputError(fmt::format("{}:{}: centre outside the box [0, {}] of {} (is this the right configuration?)",
                                     state_file, spheres.line[i], length, config.source));
    }
  }
  return spheres;
}

template <int D>
void read_final_state(const RunDirectory& run, Frame<D>& frame, Particles<D>& particles,
                      std::vector<Spin<D>>* angular_velocity) {
  const Box<D> box{resolved_box_length(run.config), run.config.system.boundary};
  SphereTable<D> table = read_state_in_box<D>(run.path("final.csv"), run.config);
  if (angular_velocity) *angular_velocity = table.spin;
  // The state read back is at its own time 0: that is the run's final instant.
  const State<D> state = assemble_state(box, std::move(table));
  frame = capture_frame(state, 0.0, 0);
  frame.time = run.final_time;
  particles = particles_of(state);
}

template SphereTable<2> read_state_in_box<2>(const std::string&, const Config&);
template SphereTable<3> read_state_in_box<3>(const std::string&, const Config&);
template void read_final_state<2>(const RunDirectory&, Frame<2>&, Particles<2>&, std::vector<Spin<2>>*);
template void read_final_state<3>(const RunDirectory&, Frame<3>&, Particles<3>&, std::vector<Spin<3>>*);

}  // namespace ballagg
