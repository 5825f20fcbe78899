#pragma once
// How long the threads of this process have waited for a CPU: the time each spent runnable
// but not running, which Linux reports per thread in /proc/self/task/<tid>/schedstat (the
// second number, nanoseconds; kernels built with CONFIG_SCHED_INFO, as distributions' are).
// A thread that waits while the process has work for it is a core taken by something else.
#include <cstdint>
#include <map>
#include <optional>

namespace ballagg {

class RunDelayMeter {
 public:
  // The seconds the process's threads waited in all since the previous call (since the
  // meter was made, for the first), counting each thread from its previous reading or, for
  // a thread started since, from its start. A thread that ended in between takes its last
  // interval with it: the sum is of the threads alive now. nullopt where the kernel does
  // not report the waits.
  std::optional<double> waited_since_last();

 private:
  std::map<long, std::uint64_t> last_ns_;  // per thread id: its total wait at the last reading
  bool started_ = false;
};

}  // namespace ballagg
