#include "ballagg/core/adaptive_team.hpp"

#include <atomic>
#include <cstdlib>
#include <optional>

#include "ballagg/core/cpu_load.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/core/run_delay.hpp"
#include "ballagg/core/team_size_rule.hpp"

namespace ballagg {
namespace {

using Clock = std::chrono::steady_clock;

std::atomic<int> pinned_teams{0};

// A run's end reads the threads' waits (tens of microseconds: a /proc file per thread)
// only after this much running since the last reading. A shorter run followed by another
// within kTeamSampleSeconds is measured together with it, the time between them counted as
// running: a loop of short runs (the Python module's `sim.run` calls) then reads the waits
// once a sample, not twice a run.
constexpr double kTeamReadAtRunEndSeconds = 0.002;

// What one thread's runs have found so far: the rule's state, the wait readings, and the
// part of a sample gathered by runs too short to complete one.
struct TeamHistory {
  std::optional<TeamSizeRule> rule;
  RunDelayMeter meter;
  double read_wall = 0.0;     // running gathered up to the meter's last reading, not yet sampled
  double read_waiting = 0.0;  // the waits of read_wall
  double unread_wall = 0.0;   // running since the meter's last reading, before the current run
  std::optional<Clock::time_point> last_end;  // when the last run ended
};

TeamHistory& history() {
  thread_local TeamHistory h;
  return h;
}

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

bool is_set(const char* value) { return value != nullptr && value[0] != '\0'; }

void set_team(int threads) {
#ifdef _OPENMP
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
}

bool in_parallel_region() {
#ifdef _OPENMP
  return omp_get_level() > 0;
#else
  return false;
#endif
}

}  // namespace

TeamSizing team_sizing_from_environment(const char* omp_num_threads, const char* omp_dynamic) {
  return is_set(omp_num_threads) || is_set(omp_dynamic) ? TeamSizing::openmp : TeamSizing::adaptive;
}

PinnedTeamSize::PinnedTeamSize() { ++pinned_teams; }
PinnedTeamSize::~PinnedTeamSize() { --pinned_teams; }

AdaptiveTeam::AdaptiveTeam() : caller_threads_(max_threads()) {
  if (pinned_teams > 0 || caller_threads_ <= 1 || in_parallel_region()) return;
  if (team_sizing_from_environment(std::getenv("OMP_NUM_THREADS"), std::getenv("OMP_DYNAMIC")) != TeamSizing::adaptive)
    return;
  TeamHistory& h = history();
  const Clock::time_point now = Clock::now();
  bool read_past_gap = true;
  if (!h.rule || h.rule->max_team() != caller_threads_) {
    h.rule.emplace(caller_threads_);
    h.read_wall = h.read_waiting = 0.0;
    // A first step may hold thousands of regions: it starts with the cores free now.
    if (const std::optional<int> elsewhere = runnable_elsewhere()) {
      const int team = starting_team(caller_threads_, allowed_cpus(), *elsewhere);
      h.rule->start_with(team, seconds(now.time_since_epoch()));
    }
  } else if (h.last_end && seconds(now - *h.last_end) <= kTeamSampleSeconds) {
    h.unread_wall += seconds(now - *h.last_end);  // a short gap counts as running
    read_past_gap = false;
  }
  // The waits since the last reading are the gap's (and those of a short run's end): not
  // this run's.
  if (read_past_gap) {
    if (!h.meter.waited_since_last()) return;
    h.unread_wall = 0.0;
  }
  active_ = true;
  segment_start_ = now;
  sample_due_ = now + std::chrono::duration_cast<Clock::duration>(
                          std::chrono::duration<double>(kTeamSampleSeconds - h.read_wall - h.unread_wall));
  set_team(h.rule->team());
}

AdaptiveTeam::~AdaptiveTeam() {
  if (!active_) return;
  TeamHistory& h = history();
  const Clock::time_point now = Clock::now();
  h.unread_wall += seconds(now - segment_start_);
  if (h.unread_wall >= kTeamReadAtRunEndSeconds) {
    if (const std::optional<double> waited = h.meter.waited_since_last()) {
      h.read_waiting += *waited;
      h.read_wall += h.unread_wall;
      h.unread_wall = 0.0;
    }
  }
  h.last_end = now;
  set_team(caller_threads_);
}

void AdaptiveTeam::sample() {
  TeamHistory& h = history();
  const std::optional<double> waited = h.meter.waited_since_last();
  const Clock::time_point now = Clock::now();
  if (!waited) {  // the readings stopped: the team OpenMP gives
    active_ = false;
    set_team(caller_threads_);
    return;
  }
  const double wall = h.read_wall + h.unread_wall + seconds(now - segment_start_);
  const double waiting = h.read_waiting + *waited;
  set_team(h.rule->after_sample(seconds(now.time_since_epoch()), wall, waiting));
  h.read_wall = h.read_waiting = h.unread_wall = 0.0;
  segment_start_ = now;
  sample_due_ = now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kTeamSampleSeconds));
}

}  // namespace ballagg
