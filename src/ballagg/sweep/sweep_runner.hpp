#pragma once
// The `ballagg sweep` command: every run of a sweep, in parallel on the local cores (one
// thread per concurrent run) and across MPI ranks, each run in its own directory
// (runs/p007-r03: the files of `ballagg run` plus those of `ballagg analyze`). A run is
// finished when its summary.json exists (written last, atomically): a resumed sweep skips
// it. At the end the first process writes the tables of sweep_table.hpp.
//
// A signal (SIGINT, SIGTERM, SIGHUP; the caller installs the handlers, run/checkpointer.hpp)
// stops the runs under way, which leave nothing (they start again when the sweep is
// resumed), and starts no new one; the tables of the runs done are written all the same.
#include <string>

#include "ballagg/sweep/communicator.hpp"
#include "ballagg/sweep/sweep_spec.hpp"

namespace ballagg {

struct SweepOptions {
  std::string out_dir;       // the sweep directory
  bool resume = false;       // continue the sweep already in out_dir
  int jobs = 0;              // concurrent runs per process; 0: the cores (1 under MPI)
  int threads_per_run = 1;   // OpenMP threads of each run
  bool quiet = false;        // no progress lines (sweep_progress.hpp)
};

struct SweepOutcome {
  long long ran = 0, skipped = 0, failed = 0;  // over all processes
  long long total = 0;                         // runs of the sweep
  int signal = 0;                              // the signal that stopped the sweep, or 0
};

// Throws InputError (before running anything) for a bad sweep file or directory.
SweepOutcome run_sweep(const SweepSpec& spec, const SweepOptions& options, const Communicator& world);

}  // namespace ballagg
