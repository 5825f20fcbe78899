#include "ballagg/core/cpu_load.hpp"

#include <dirent.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

namespace ballagg {
namespace {

// The runnable threads of the whole system, the first number of "R/T" in /proc/loadavg.
std::optional<int> runnable_in_system() {
  std::FILE* f = std::fopen("/proc/loadavg", "r");
  if (!f) return std::nullopt;
  double load1 = 0, load5 = 0, load15 = 0;
  int runnable = 0, threads = 0;
  const int read = std::fscanf(f, "%lf %lf %lf %d/%d", &load1, &load5, &load15, &runnable, &threads);
  std::fclose(f);
  if (read != 5) return std::nullopt;
  return runnable;
}

// Whether a thread of this process is runnable: the state letter after the command name
// (which may hold spaces and parentheses, hence the last ')').
bool thread_runnable(const char* tid) {
  const std::string path = std::string("/proc/self/task/") + tid + "/stat";
  std::FILE* f = std::fopen(path.c_str(), "r");
  if (!f) return false;
  char text[512];
  const std::size_t size = std::fread(text, 1, sizeof text - 1, f);
  std::fclose(f);
  text[size] = '\0';
  const char* close = std::strrchr(text, ')');
  return close != nullptr && close[1] == ' ' && close[2] == 'R';
}

std::optional<int> runnable_in_process() {
  DIR* tasks = opendir("/proc/self/task");
  if (!tasks) return std::nullopt;
  int runnable = 0;
  while (const dirent* e = readdir(tasks))
    if (e->d_name[0] != '.' && thread_runnable(e->d_name)) ++runnable;
  closedir(tasks);
  return runnable;
}

}  // namespace

int allowed_cpus() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  return std::max(1, CPU_COUNT(&set));
}

std::optional<int> runnable_elsewhere() {
  std::optional<int> least;
  for (int k = 0; k < kBusyReadings; ++k) {
    if (k > 0) std::this_thread::sleep_for(std::chrono::duration<double>(kBusyReadingGapSeconds));
    const std::optional<int> system = runnable_in_system();
    const std::optional<int> own = runnable_in_process();
    if (!system || !own) return std::nullopt;
    const int elsewhere = std::max(0, *system - *own);
    least = least ? std::min(*least, elsewhere) : elsewhere;
  }
  return least;
}

}  // namespace ballagg
