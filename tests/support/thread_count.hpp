#pragma once
// Results must never depend on the number of OpenMP threads (docs/performance.md): helpers
// that run the same thing on one thread and on two, in the test's own process.
#include <omp.h>

#include <filesystem>
#include <map>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "ballagg/config/config.hpp"
#include "ballagg/core/adaptive_team.hpp"
#include "ballagg/run/simulation.hpp"
#include "cli_support.hpp"
#include "support.hpp"

namespace ballagg::testing {

// The OpenMP thread count of the calling thread for the object's lifetime, kept by the
// runs whatever the load (core/adaptive_team.hpp); the previous count is restored when it goes.
class ThreadCount {
 public:
  explicit ThreadCount(int threads) : previous_(omp_get_max_threads()) { omp_set_num_threads(threads); }
  ~ThreadCount() { omp_set_num_threads(previous_); }
  ThreadCount(const ThreadCount&) = delete;
  ThreadCount& operator=(const ThreadCount&) = delete;

 private:
  PinnedTeamSize pinned_;
  int previous_;
};

// f() on one thread, then on two: the pair of results, to be compared by the caller.
template <class F>
auto on_one_and_two_threads(F&& f) {
  auto on = [&](int threads) {
    const ThreadCount count(threads);
    return f();
  };
  auto one = on(1);
  auto two = on(2);
  return std::pair{std::move(one), std::move(two)};
}

// Every file of the directory `dir` by name, summary.json without the fields that measure
// the wall clock (wall_seconds, events_per_second): what must come out byte for byte the
// same from the same configuration and seed.
inline std::map<std::string, std::string> reproducible_files(const std::filesystem::path& dir) {
  std::map<std::string, std::string> files;
  for (const std::filesystem::directory_entry& e : std::filesystem::directory_iterator(dir))
    files[e.path().filename().string()] = slurp(e.path());
  if (files.count("summary.json")) {
    nlohmann::ordered_json summary = nlohmann::ordered_json::parse(files["summary.json"]);
    summary.erase("wall_seconds");
    summary.erase("events_per_second");
    files["summary.json"] = summary.dump(2);
  }
  return files;
}

// The files of a run of `config` in scratch/run, removed afterwards: runs to compare are
// made in the same directory, whose path some files record (analysis.json).
inline std::map<std::string, std::string> files_of_run(const Config& config, const TempDir& scratch) {
  RunOptions options;
  options.out_dir = (scratch / "run").string();
  options.quiet = true;
  options.progress_on_terminal = false;
  options.checkpoint_on_signals = false;
  run_simulation(config, options);
  std::map<std::string, std::string> files = reproducible_files(options.out_dir);
  std::filesystem::remove_all(options.out_dir);
  return files;
}

// Expects the same files, each byte for byte, naming the first that differs.
inline void expect_same_files(const std::map<std::string, std::string>& one,
                              const std::map<std::string, std::string>& two) {
  std::string names_one, names_two;
  for (const auto& entry : one) names_one += entry.first + " ";
  for (const auto& entry : two) names_two += entry.first + " ";
  ASSERT_EQ(names_one, names_two);
  for (const auto& entry : one) EXPECT_TRUE(entry.second == two.at(entry.first)) << entry.first << " differs";
}

}  // namespace ballagg::testing
