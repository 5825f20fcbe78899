#pragma once
// The number of OpenMP threads of an engine's parallel regions on a machine that others
// share: by default a run takes as many threads as OpenMP gives (a core each) and gives
// threads up while they wait for a CPU, by the rule of team_size_rule.hpp, measured by
// run_delay.hpp. Setting OMP_NUM_THREADS or OMP_DYNAMIC leaves the team to OpenMP: the
// number of threads asked for, or the runtime's own adjustment (docs/time_stepping.md#threads).
#include <chrono>

namespace ballagg {

enum class TeamSizing {
  adaptive,  // ballagg shrinks the team while a core is taken (the default)
  openmp,    // the team is what the OpenMP settings give (OMP_NUM_THREADS, OMP_DYNAMIC)
};

// The sizing the environment asks for, given the values of OMP_NUM_THREADS and
// OMP_DYNAMIC (nullptr when unset): a user who set either chose the team.
TeamSizing team_sizing_from_environment(const char* omp_num_threads, const char* omp_dynamic);

// While one lives, every run keeps the team its OpenMP settings give, whatever the
// environment says (tests that compare thread counts; any thread may make one).
class PinnedTeamSize {
 public:
  PinnedTeamSize();
  ~PinnedTeamSize();
  PinnedTeamSize(const PinnedTeamSize&) = delete;
  PinnedTeamSize& operator=(const PinnedTeamSize&) = delete;
};

// The team of the calling thread's parallel regions for the lifetime of one engine run.
// It starts from what the calling thread's previous runs found (the machine does not
// change with the run: a program making many short runs, as the Python module's callers
// do, keeps measuring across them), and poll(), called between parallel regions, measures
// and applies the rule. The calling thread's own OpenMP thread count is restored at the end.
// Does nothing inside a parallel region (whose team was chosen around it), with one
// thread, under TeamSizing::openmp, or where the kernel does not report waits.
class AdaptiveTeam {
 public:
  AdaptiveTeam();
  ~AdaptiveTeam();
  AdaptiveTeam(const AdaptiveTeam&) = delete;
  AdaptiveTeam& operator=(const AdaptiveTeam&) = delete;

  // Cheap (a clock reading) until a sample is due.
  void poll() {
    if (active_ && std::chrono::steady_clock::now() >= sample_due_) sample();
  }

 private:
  void sample();

  bool active_ = false;
  int caller_threads_ = 1;
  std::chrono::steady_clock::time_point segment_start_{};
  std::chrono::steady_clock::time_point sample_due_{};
};

}  // namespace ballagg
