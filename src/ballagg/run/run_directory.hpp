#pragma once
// Reading a finished run's directory (what `ballagg run` wrote), for `ballagg analyze` and
// `ballagg render`: its configuration, the final state (final.csv, at the time in
// summary.json) and the trajectory. Every problem is an InputError naming the file.
#include <string>

#include "ballagg/config/config.hpp"
#include "ballagg/io/frame.hpp"
#include "ballagg/io/state_csv.hpp"

namespace ballagg {

struct RunDirectory {
  std::string dir;
  Config config;           // config.toml
  double final_time = 0.0; // summary.json "time"
  std::string path(const std::string& name) const;
};

RunDirectory open_run_directory(const std::string& dir);

// A state file (final.csv, or any file in its format) for the box of `config`: every
// centre must lie in [0, L], which catches a file paired with another run's configuration.
template <int D>
SphereTable<D> read_state_in_box(const std::string& state_file, const Config& config);

// The final state as a frame (clusters unwrapped across periodic faces, as in the run),
// and, when final.csv has spin columns (rigid-body runs) and angular_velocity is given,
// each sphere's angular velocity (its body's).
template <int D>
void read_final_state(const RunDirectory& run, Frame<D>& frame, Particles<D>& particles,
                      std::vector<Spin<D>>* angular_velocity = nullptr);

}  // namespace ballagg
