#pragma once
// From a configuration to a finished run: initial state, engine, observers, output files.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ballagg/config/config.hpp"
#include "ballagg/engines/engine.hpp"

namespace ballagg {

// Fills the keys whose defaults depend on the initial state (engine.skin, and
// collision.tc_time for bounces), so the resolved config reproduces the run exactly.
template <int D>
Config resolve_defaults(Config c, const State<D>& initial);

template <int D>
std::unique_ptr<Engine<D>> make_engine(const Config& resolved);

StopCriteria stop_criteria(const Config& c);

struct RunOptions {
  std::string out_dir;         // empty: out/<timestamp>
  bool quiet = false;
  bool progress_on_terminal = true;  // redraw a bar if stderr is a terminal
  // SIGINT and SIGTERM write a checkpoint and end the run (RunInterrupted). Off for runs
  // inside another program (sweeps on threads, Python).
  bool checkpoint_on_signals = true;
  // A new run into a directory that holds another run's files replaces them (removes
  // them first); without it such a directory is refused (run/run_files.hpp).
  bool overwrite = false;
};

// The `ballagg run` command. Validates everything (throws InputError) before creating
// the output directory, then runs and writes summary.json, timeseries.csv, final.csv and
// final.xyz. Returns the output directory. The directory is locked while the run writes
// it, and must not hold another run unless options.overwrite (open_new_run_directory).
// Checkpoints (output.checkpoint_every, signals) are written to the output directory's
// checkpoint.bin, which is removed when the run finishes.
std::string run_simulation(const Config& config, const RunOptions& options);

// `ballagg run --resume DIR`: continues the run of DIR from its checkpoint.bin and
// finishes it as the uninterrupted run would have (the same files, byte for byte, but
// for the wall times). options.out_dir is ignored. Throws CheckpointError (an InputError)
// when DIR holds no usable checkpoint, and InputError when another process writes DIR.
std::string resume_simulation(const std::string& dir, const RunOptions& options);

}  // namespace ballagg
