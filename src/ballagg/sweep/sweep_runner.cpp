#include "ballagg/sweep/sweep_runner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <optional>
#include <thread>

#include <fmt/format.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "ballagg/config/text_file.hpp"
#include "ballagg/core/run_guard.hpp"
#include "ballagg/io/directory_lock.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/run/analyze_run.hpp"
#include "ballagg/run/checkpointer.hpp"
#include "ballagg/run/simulation.hpp"
#include "ballagg/sweep/sweep_progress.hpp"
#include "ballagg/sweep/sweep_table.hpp"

namespace ballagg {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSweepCopy = "sweep.toml";  // the sweep file as started, in the sweep directory

fs::path run_dir(const SweepOptions& o, const SweepRun& r) { return fs::path(o.out_dir) / "runs" / r.name; }

// A directory with no file but the lock file a killed sweep may leave.
bool empty_but_for_a_lock(const fs::path& dir) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (e.path().filename() != kLockFile) return false;
  return !ec;
}

// Checks that out_dir can hold this sweep: a fresh or empty directory, or (with --resume)
// one started from the same sweep file. Every process checks, only the first writes.
void check_sweep_dir(const SweepSpec& spec, const SweepOptions& o) {
  const fs::path copy = fs::path(o.out_dir) / kSweepCopy;
  std::error_code ec;
  if (fs::exists(o.out_dir, ec) && !fs::is_directory(o.out_dir, ec))
    throw InputError(fmt::format("--out {}: exists and is not a directory", o.out_dir));
  if (fs::exists(copy, ec)) {
    if (!o.resume)
      throw InputError(fmt::format("--out {}: holds a sweep already (use --resume to continue it, or another --out)",
                                   o.out_dir));
    if (read_text_file(copy.string(), "sweep copy", kMaxSettingsFileBytes) != spec.text)
      throw InputError(fmt::format("{}: differs from {}, the file this sweep was started with (a resumed sweep must "
                                   "keep its grid)", spec.source, copy.string()));
    return;
  }
  if (fs::exists(o.out_dir, ec) && !empty_but_for_a_lock(o.out_dir))
    throw InputError(fmt::format("--out {}: not empty and not a sweep directory (no {})", o.out_dir, kSweepCopy));
}

bool finished(const fs::path& dir) { return fs::exists(dir / "summary.json"); }
bool analysed(const fs::path& dir) { return fs::exists(dir / "analysis.json"); }

// The first process locks the sweep directory for the whole sweep: a second sweep started
// on it (with --resume or not) is refused by every process of its job. It then keeps the
// sweep file and makes runs/.
std::optional<DirectoryLock> lock_sweep_dir(const SweepSpec& spec, const SweepOptions& o, const Communicator& world) {
  std::optional<DirectoryLock> lock;
  std::string refusal;
  if (world.rank() == 0) {
    const bool created = prepare_output_dir(o.out_dir);
    try {
      lock.emplace(o.out_dir);
    } catch (const InputError& e) {
      refusal = e.what();
      std::error_code ec;
      if (created) fs::remove(o.out_dir, ec);
    }
  }
  if (world.sum(refusal.empty() ? 0 : 1) > 0)
    throw InputError(!refusal.empty() ? refusal
                                      : fmt::format("{}: another ballagg process is writing this directory", o.out_dir));
  if (world.rank() == 0) {
    if (!fs::exists(fs::path(o.out_dir) / kSweepCopy)) write_file_atomically(o.out_dir, kSweepCopy, spec.text);
    fs::create_directories(fs::path(o.out_dir) / "runs");
  }
  return lock;
}

// This process's runs still to do: every size-th, so each point's realizations spread over
// the ranks; those finished and analysed are counted in `skipped`.
std::vector<const SweepRun*> runs_to_do(const std::vector<SweepRun>& runs, const SweepOptions& o,
                                        const Communicator& world, long long& skipped) {
  std::vector<const SweepRun*> mine;
  for (std::size_t k = world.rank(); k < runs.size(); k += world.size()) {
    const fs::path dir = run_dir(o, runs[k]);
    if (finished(dir) && analysed(dir)) ++skipped;
    else mine.push_back(&runs[k]);
  }
  return mine;
}

int jobs_of(const SweepOptions& o, const Communicator& world) {
  if (o.jobs > 0) return o.jobs;
  return std::max(1, world.mpi() ? 1 : static_cast<int>(std::thread::hardware_concurrency()));
}

// " (rank 2 of 4)" under MPI with more than one process, else nothing.
std::string process_name(const Communicator& world) {
  return world.size() > 1 ? fmt::format(" (rank {} of {})", world.rank(), world.size()) : std::string();
}

// One run and its analysis. An unfinished run (the sweep was stopped during it) starts
// again from the beginning, replacing its files.
void run_and_analyse(const SweepRun& r, const fs::path& dir) {
  RunOptions options{dir.string(), true, false, false};
  options.overwrite = true;
  if (!finished(dir)) run_simulation(r.config, options);
  analyze_run({dir.string(), "", "", ""});
  std::error_code ec;
  fs::remove(dir / "error.txt", ec);  // left by an earlier attempt
}

// A failed run leaves its message in error.txt (and on stderr, by SweepProgress).
void record_failure(const fs::path& dir, const std::string& what) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  try {
    write_file_atomically(dir.string(), "error.txt", what + "\n");
  } catch (const std::exception&) {
    // The message is on stderr already.
  }
}

struct RunCounts {
  std::atomic<long long> ran{0}, failed{0};
};

// Runs `mine` on `jobs` threads (this one included), each taking the next run not taken.
void run_all(const std::vector<const SweepRun*>& mine, const std::vector<SweepPoint>& points, const SweepOptions& o,
             int jobs, SweepProgress& progress, RunCounts& counts) {
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
#ifdef _OPENMP
    omp_set_num_threads(std::max(1, o.threads_per_run));  // per thread: each run's own team
#endif
    for (std::size_t k; stop_signal() == 0 && (k = next++) < mine.size();) {
      const SweepRun& r = *mine[k];
      const fs::path dir = run_dir(o, r);
      const auto start = std::chrono::steady_clock::now();
      const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
      try {
        run_and_analyse(r, dir);
        ++counts.ran;
        progress.done(r, points[r.point], seconds());
      } catch (const RunInterrupted&) {
        // Stopped under way: it runs again when the sweep is resumed. Its files are gone
        // already; the directory made for it goes too, so that runs/ holds finished runs
        // only (remove() leaves a directory that is not empty).
        std::error_code ec;
        fs::remove(dir, ec);
      } catch (const std::exception& e) {
        ++counts.failed;
        progress.failed(dir.string(), e.what(), seconds());
        record_failure(dir, e.what());
      }
    }
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < std::min<int>(jobs, static_cast<int>(mine.size())); ++t) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
}

}  // namespace

SweepOutcome run_sweep(const SweepSpec& spec, const SweepOptions& o, const Communicator& world) {
  const std::vector<SweepPoint> points = sweep_points(spec);
  const std::vector<SweepRun> runs = sweep_runs(spec, points);  // every configuration checked
  check_sweep_dir(spec, o);
  world.barrier();  // every process has checked before the first writes
  const std::optional<DirectoryLock> lock = lock_sweep_dir(spec, o, world);
  world.barrier();

  long long skipped = 0;
  const std::vector<const SweepRun*> mine = runs_to_do(runs, o, world, skipped);
  const int jobs = jobs_of(o, world);
  SweepProgress progress(spec, stdout, o.quiet, static_cast<long long>(mine.size()), jobs, process_name(world));
  progress.start(skipped);
  RunCounts counts;
  run_all(mine, points, o, jobs, progress, counts);

  SweepOutcome out{world.sum(counts.ran), world.sum(skipped), world.sum(counts.failed),
                   static_cast<long long>(runs.size()), stop_signal()};
  world.barrier();  // every run is on disk
  if (world.rank() == 0) write_sweep_tables(o.out_dir, spec, points, runs);
  return out;
}

}  // namespace ballagg
