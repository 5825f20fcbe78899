#pragma once
// What `ballagg sweep` says while it runs (docs/sweeps.md): a line when it starts, then one
// per finished run, with its rank among this process's runs, the parameters that set its
// point apart (the variant's label and the grid values) and an estimate of the time left:
//
//   sweep: [3/8] about 4 s left (estimate); runs/p001-r00 (ts rigid: system.n = 25) done
//
// The estimate takes the mean computing time of the runs finished so far, times the runs
// still to finish, over the runs at once (--jobs): each run's own time is measured, so the
// estimate does not depend on how many run side by side. Under MPI each process counts
// its own runs and names itself: "sweep (rank 1 of 4): [3/8] ...". --quiet silences the lines; a
// failed run's message goes to stderr all the same.
#include <cstdio>
#include <mutex>
#include <string>

#include "ballagg/sweep/sweep_spec.hpp"

namespace ballagg {

// "ts rigid: system.n = 25, ts.dt_factor = 0.01": the variant's label (when the sweep file
// has [[variants]]) and the grid values of a point, as written in the sweep file.
std::string point_parameters(const SweepSpec& spec, const SweepPoint& point);

// Seconds left for `left` runs of `mean_seconds` each, `jobs` at a time.
double estimated_seconds_left(double mean_seconds, long long left, int jobs);

// "about 40 s", "about 12 min", "about 3.5 h", "under 1 s": a duration in the unit a
// reader takes in at a glance.
std::string approximate_duration(double seconds);

class SweepProgress {
 public:
  // `runs`: the runs this process is to run; `jobs`: how many at once; `process`: its name
  // in each line (" (rank 1 of 4)" under MPI), or empty.
  SweepProgress(const SweepSpec& spec, std::FILE* out, bool quiet, long long runs, int jobs, std::string process);

  // The first line: the runs to do, those finished already, how many at once.
  void start(long long already_finished);
  // A run is done (or failed: its message goes to stderr); safe to call from every worker.
  void done(const SweepRun& run, const SweepPoint& point, double seconds);
  void failed(const std::string& run_dir, const std::string& what, double seconds);

 private:
  // Counts a run, under mutex_; returns its rank (1 ... runs) and the time-left estimate.
  std::pair<long long, double> count(double seconds);

  const SweepSpec& spec_;
  std::FILE* out_;
  bool quiet_;
  long long runs_;
  int jobs_;
  std::string process_;
  std::mutex mutex_;
  long long finished_ = 0;
  double seconds_ = 0.0;  // the finished runs' computing time
};

}  // namespace ballagg
