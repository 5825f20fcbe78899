#pragma once
// How many OpenMP threads the next parallel regions use, decided from what the threads of
// this process waited for a CPU. A parallel region ends when its last thread does, and the
// engines open many short regions per step: when another process holds a core, a team as
// large as the cores runs each region at the pace of a thread that waits a scheduler time
// slice for its turn, and fewer threads finish sooner (docs/performance.md, "On a shared
// machine"). The rule gives threads up while its threads wait for CPUs, one per core's
// worth waited, and tries the full team again after a while, waiting longer after each try
// that fails, so that a run takes back the cores soon after they are free, at a bounded
// cost while they are not. Thread counts never change results
// (docs/time_stepping.md#threads), so the team may change between any two regions.
#include <algorithm>
#include <cmath>

namespace ballagg {

// A measure is taken over at least this much wall time: a few scheduler time slices, so
// that a busy core shows in what the threads waited, short enough that a run on a taken
// core is noticed before it has lost much.
inline constexpr double kTeamSampleSeconds = 0.02;
// The team shrinks when its threads waited, together, at least this many cores' worth of
// the sample (waiting time / wall time): a team beside a busy process waits about half a
// core's worth, one alone a few hundredths (docs/time_stepping.md, "On a shared machine"),
// and the threshold lies well between.
inline constexpr double kTeamWaitingToShrink = 0.25;
// After the team shrank, the full team is tried again this long after (seconds)...
inline constexpr double kFirstTeamRetrySeconds = 0.25;
// ...and, each time the try shows the cores still taken, twice as long after, up to this.
inline constexpr double kLongestTeamRetrySeconds = 8.0;

// The team to start with before any wait is measured: a core for each thread, of the CPUs
// this process may use less those that other processes' runnable threads hold.
inline int starting_team(int max_team, int allowed_cpus, int runnable_elsewhere) {
  return std::clamp(allowed_cpus - runnable_elsewhere, 1, std::max(1, max_team));
}

class TeamSizeRule {
 public:
  explicit TeamSizeRule(int max_team) : max_team_(std::max(1, max_team)), team_(max_team_) {}

  int team() const { return team_; }
  int max_team() const { return max_team_; }

  // Starts with `team` threads at time `now` (starting_team); when fewer than the full
  // team, the full team is tried as after a shrink.
  void start_with(int team, double now) {
    team_ = std::clamp(team, 1, max_team_);
    if (team_ < max_team_) retry_at_ = now + retry_wait_;
  }

  // A sample: over `wall` seconds ending at `now` (seconds, any origin), the threads of the
  // team, `team()` of them, waited `waiting` seconds in all for a CPU. Returns the team
  // for the next regions.
  int after_sample(double now, double wall, double waiting) {
    const double waiting_cores = wall > 0.0 ? waiting / wall : 0.0;
    const bool tried = trying_;
    trying_ = false;
    if (team_ > 1 && waiting_cores >= kTeamWaitingToShrink) {
      const int fewer = std::max(1, static_cast<int>(std::lround(waiting_cores)));
      team_ = std::max(1, team_ - fewer);
      retry_wait_ = tried ? std::min(2.0 * retry_wait_, kLongestTeamRetrySeconds) : kFirstTeamRetrySeconds;
      retry_at_ = now + retry_wait_;
    } else if (team_ < max_team_ && now >= retry_at_) {
      team_ = max_team_;
      trying_ = true;
    }
    return team_;
  }

 private:
  int max_team_;
  int team_;
  bool trying_ = false;  // the team was grown at the last sample and not yet measured
  double retry_wait_ = kFirstTeamRetrySeconds;
  double retry_at_ = 0.0;
};

}  // namespace ballagg
