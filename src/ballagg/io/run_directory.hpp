#pragma once
// Reading a finished run's directory (what `ballagg run` wrote): its configuration, the
// final state (final.csv, at the time in summary.json) and the trajectory. Every problem
// is an InputError naming the file.
#include <string>

#include "ballagg/config/config.hpp"
#include "ballagg/io/frame.hpp"

namespace ballagg {

struct RunDirectory {
  std::string dir;
  Config config;           // config.toml
  double final_time = 0.0; // summary.json "time"
  std::string path(const std::string& name) const;
};

RunDirectory open_run_directory(const std::string& dir);

// The final state as a frame (clusters unwrapped across periodic faces, as in the run).
template <int D>
void read_final_state(const RunDirectory& run, Frame<D>& frame, Particles<D>& particles);

}  // namespace ballagg
