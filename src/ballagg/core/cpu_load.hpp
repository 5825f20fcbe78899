#pragma once
// A glance at how busy the machine is now, for the team of a process's first parallel
// regions, before its own threads' waits can be measured (run_delay.hpp).
#include <optional>

namespace ballagg {

// The CPUs this process may run on (its affinity mask; at least 1).
int allowed_cpus();

// The threads of other processes that are runnable now: the runnable threads of the
// system (/proc/loadavg, fourth field) less this process's own (state R in
// /proc/self/task/*/stat), the least of kBusyReadings readings kBusyReadingGapSeconds apart,
// so that a process running for an instant is not taken for one that holds a core.
// nullopt where /proc does not tell.
std::optional<int> runnable_elsewhere();

inline constexpr int kBusyReadings = 4;
inline constexpr double kBusyReadingGapSeconds = 0.0005;

}  // namespace ballagg
