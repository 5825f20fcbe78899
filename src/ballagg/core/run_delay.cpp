#include "ballagg/core/run_delay.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <utility>

namespace ballagg {
namespace {

// The total wait of one thread (the second number of its schedstat), nullopt if unreadable
// (the thread ended, or the kernel does not report it). Plain system calls: a reading is
// made for every thread at every sample.
std::optional<std::uint64_t> thread_wait_ns(int task_dir, const char* tid) {
  char path[sizeof(dirent::d_name) + 16];
  std::snprintf(path, sizeof path, "%s/schedstat", tid);
  const int fd = openat(task_dir, path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  char text[96];
  const ssize_t size = read(fd, text, sizeof text - 1);
  close(fd);
  if (size <= 0) return std::nullopt;
  text[size] = '\0';
  unsigned long long running = 0, waiting = 0;
  if (std::sscanf(text, "%llu %llu", &running, &waiting) != 2) return std::nullopt;
  return static_cast<std::uint64_t>(waiting);
}

}  // namespace

std::optional<double> RunDelayMeter::waited_since_last() {
  DIR* tasks = opendir("/proc/self/task");
  if (!tasks) return std::nullopt;
  std::map<long, std::uint64_t> now_ns;
  while (const dirent* e = readdir(tasks)) {
    char* end = nullptr;
    const long tid = std::strtol(e->d_name, &end, 10);
    if (end == e->d_name || *end != '\0') continue;  // "." and ".."
    if (const std::optional<std::uint64_t> ns = thread_wait_ns(dirfd(tasks), e->d_name)) now_ns.emplace(tid, *ns);
  }
  closedir(tasks);
  if (now_ns.empty()) return std::nullopt;
  std::uint64_t waited = 0;
  if (started_)
    for (const auto& [tid, ns] : now_ns) {
      const auto last = last_ns_.find(tid);
      const std::uint64_t from = last == last_ns_.end() ? 0 : last->second;
      if (ns > from) waited += ns - from;
    }
  last_ns_ = std::move(now_ns);
  started_ = true;
  return static_cast<double>(waited) * 1e-9;
}

}  // namespace ballagg
