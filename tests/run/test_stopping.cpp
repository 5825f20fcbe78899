// Every loop of a run observes stop.wall_seconds and the signals (core/run_guard.hpp):
// rows and frames due before one event, long minimisations of the time-stepping engine,
// sweeps; a second signal never leaves a temporary file; output that would have no end is
// refused or capped (docs/hardening.md, "Signals and the wall clock").
#include <csignal>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ballagg/core/run_guard.hpp"
#include "ballagg/io/checkpoint_file.hpp"
#include "ballagg/run/snapshots.hpp"
#include "cli_support.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

namespace fs = std::filesystem;
using testing::exit_status;
using testing::run_ballagg;
using testing::slurp;
using testing::start_ballagg;
using testing::TempDir;
using testing::wait_until;

std::vector<std::string> run_args(const fs::path& out, const std::vector<std::string>& sets) {
  std::vector<std::string> args{"run", "--quiet", "--out", out.string()};
  for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
  return args;
}

std::string stop_reason(const fs::path& run) {
  return nlohmann::json::parse(slurp(run / "summary.json")).at("stop_reason").get<std::string>();
}

// The time column of timeseries.csv.
std::vector<double> row_times(const fs::path& run) {
  std::istringstream in(slurp(run / "timeseries.csv"));
  std::string line;
  std::getline(in, line);
  std::vector<double> times;
  while (std::getline(in, line)) times.push_back(std::stod(line.substr(0, line.find(','))));
  return times;
}

// The files of the directory whose names end in .tmp.
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".tmp") found.push_back(e.path().filename().string());
  return found;
}

// Starts `args` and waits until the run directory exists (the signal handlers are
// installed then) and `settle_ms` more.
pid_t start_run(const std::vector<std::string>& args, const fs::path& run, const fs::path& log, int settle_ms) {
  const pid_t pid = start_ballagg(args, log);
  EXPECT_TRUE(wait_until([&] { return fs::exists(run); }, 30.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(settle_ms));
  return pid;
}

// ---- the guard ---------------------------------------------------------------------------

TEST(RunGuard, WallClockAndSignalsStopIt) {
  RunGuard unlimited;
  EXPECT_FALSE(unlimited.check());
  RunGuard none_left(0.0);
  EXPECT_TRUE(none_left.check());
  EXPECT_EQ(none_left.cause(), StopCause::wall_seconds);
  EXPECT_TRUE(none_left.step_must_end());
  EXPECT_TRUE(none_left.step_cut());

  request_stop_by_signal(SIGTERM);
  RunGuard signalled;
  int polls = 0;
  while (!signalled.poll()) ++polls;
  EXPECT_EQ(polls, RunGuard::kPollsPerCheck - 1);
  EXPECT_EQ(signalled.cause(), StopCause::signal);
  EXPECT_FALSE(signalled.step_must_end());  // a step gets kStepSignalGraceSeconds
  clear_stop_signal();

  RunGuard capped;
  capped.stop(StopCause::output_limit);
  EXPECT_TRUE(capped.poll());
  EXPECT_EQ(stop_reason_of(capped.cause()), StopReason::output_limit);
}

// Every engine ends a run asked to stop by a signal, without a checkpointing observer,
// with stop reason `interrupted` (the caller then writes nothing).
TEST(RunGuard, EveryEngineEndsASignalledRunAsInterrupted) {
  for (const EngineKind kind : {EngineKind::ed, EngineKind::ed_naive, EngineKind::ts, EngineKind::rigid_body}) {
    Config c = testing::small_config(2, 60, 0.2, Boundary::periodic, 5);
    c.engine.kind = kind;
    State<2> s = make_initial_state<2>(c);
    c = resolve_defaults(c, s);
    RunGuard guard;
    StopCriteria stop = stop_criteria(c);
    stop.guard = &guard;
    request_stop_by_signal(SIGINT);
    RunObserver<2> nobody;
    const RunResult r = make_engine<2>(c)->run(s, stop, nobody);
    clear_stop_signal();
    EXPECT_EQ(r.reason, StopReason::interrupted) << to_string(kind);
    EXPECT_EQ(s.time, 0.0) << to_string(kind);
  }
}

// ---- output without an end ---------------------------------------------------------------

// A row every 1e-9 of simulated time and no stop.time: the rows due before the first event
// alone would take hours (and grow the memory at 35 MB/s); the wall-clock limit stops them,
// and the run ends with its files, rows in time order up to the end.
TEST(Stopping, WallClockEndsARunWritingRowsWithoutEnd) {
  TempDir tmp;
  const fs::path run = tmp / "run";
  const testing::Outcome o = run_ballagg(
      run_args(run, {"system.n=100", "output.timeseries_interval=1e-9", "stop.wall_seconds=0.3"}), tmp.path());
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(stop_reason(run), "wall_seconds");
  EXPECT_TRUE(fs::exists(run / "final.csv"));
  const std::vector<double> times = row_times(run);
  ASSERT_GT(times.size(), 1000u);
  EXPECT_TRUE(std::is_sorted(times.begin(), times.end()));
  EXPECT_EQ(times.back(), nlohmann::json::parse(slurp(run / "summary.json")).at("time").get<double>());
}

// The same for frames, each of them written to the disk (without the limit, gigabytes in seconds).
TEST(Stopping, WallClockEndsARunWritingFramesWithoutEnd) {
  TempDir tmp;
  const fs::path run = tmp / "run";
  // 200 spheres: the frame cap (kMaxFrames) would take seconds of writing, so the clock
  // ends the run first on any machine (with 4, a fast one reached the cap within 0.2 s).
  const testing::Outcome o = run_ballagg(run_args(run, {"system.n=200", "output.snapshot_every=1e-9",
                                                        "output.snapshot_formats=[\"xyz\"]", "stop.wall_seconds=0.2"}),
                                         tmp.path());
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(stop_reason(run), "wall_seconds");
  EXPECT_TRUE(fs::exists(run / "trajectory.xyz"));
  EXPECT_TRUE(temporaries(run).empty());
}

// SIGTERM while the rows before one event are being written (they would take hours): the
// run ends promptly with a checkpoint.
TEST(Stopping, SigtermDuringOutputWithoutEndEndsWithACheckpoint) {
  TempDir tmp;
  const fs::path run = tmp / "run";
  const pid_t pid = start_run(run_args(run, {"system.n=100", "output.timeseries_interval=1e-9",
                                             "output.checkpoint_every=0"}),
                              run, tmp / "log", 100);
  const auto signalled = std::chrono::steady_clock::now();
  kill(pid, SIGTERM);
  const int status = exit_status(pid, 20.0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  const std::string log = slurp(tmp / "log");
  EXPECT_EQ(status, 128 + SIGTERM) << log;
  EXPECT_CONTAINS(log, "interrupted by SIGTERM");
  EXPECT_TRUE(fs::exists(run / kCheckpointFile));
  EXPECT_LT(seconds, 30.0);
}

// Interrupted while writing the rows due before an event, the run resumes exactly where
// they stopped: the event is left for later, not handled (the resumed file is the
// uninterrupted run's, byte for byte).
TEST(Stopping, RunInterruptedWhileWritingRowsResumesIdentically) {
  TempDir tmp;
  const std::vector<std::string> sets{"system.n=20", "system.volume_fraction=0.01", "stop.time=1.5",
                                      "output.timeseries_interval=1e-5", "output.checkpoint_every=0"};
  ASSERT_EQ(run_ballagg(run_args(tmp / "ref", sets), tmp.path()).status, 0);
  const fs::path run = tmp / "run";
  const pid_t pid = start_run(run_args(run, sets), run, tmp / "log", 60);
  kill(pid, SIGINT);
  const int status = exit_status(pid);
  if (status == 0) GTEST_SKIP() << "finished before the signal";
  ASSERT_EQ(status, 128 + SIGINT) << slurp(tmp / "log");
  ASSERT_EQ(run_ballagg({"run", "--quiet", "--resume", run.string()}, tmp.path()).status, 0);
  EXPECT_TRUE(slurp(tmp / "ref" / "timeseries.csv") == slurp(run / "timeseries.csv"));
  EXPECT_TRUE(slurp(tmp / "ref" / "final.csv") == slurp(run / "final.csv"));
}

// Output that a finite stop.time would take past the caps is refused before anything is
// written, naming the key and the cap.
TEST(Stopping, IntervalsGivingTooManyRowsOrFramesAreBadInput) {
  TempDir tmp;
  const fs::path run = tmp / "run";
  testing::Outcome o =
      run_ballagg(run_args(run, {"stop.time=100", "output.timeseries_interval=1e-9"}), tmp.path());
  EXPECT_EQ(o.status, 2);
  EXPECT_CONTAINS(o.err, "ballagg: error: output.timeseries_interval = 1e-09: 1e+11 rows from t = 0 to stop.time = 100");
  EXPECT_CONTAINS(o.err, "at most 1000000");
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
  EXPECT_FALSE(fs::exists(run));
  o = run_ballagg(run_args(run, {"stop.time=100", "output.snapshot_every=1e-4"}), tmp.path());
  EXPECT_EQ(o.status, 2);
  EXPECT_CONTAINS(o.err, "output.snapshot_every = 0.0001: 1e+06 frames");
  EXPECT_CONTAINS(o.err, "at most 100000");
  EXPECT_FALSE(fs::exists(run));
  // At the caps: accepted.
  EXPECT_NO_THROW(check_timeseries_rows(1e-4, 0.0, 100.0));
  EXPECT_NO_THROW(check_snapshot_frames(1e-3, 0.0, 100.0));
}

// Without a finite stop.time, the recorders stop the run at their caps.
TEST(Stopping, RecordersStopTheRunAtTheirCaps) {
  Config c = testing::small_config(2, 4, 0.05, Boundary::walls, 3);
  State<2> s = make_initial_state<2>(c);
  RunGuard guard;
  TimeseriesRecorder<2> rows(1e-12, false, &guard);
  rows.on_start(s);
  rows.before_event(s, 1.0);  // 10^12 rows due
  EXPECT_EQ(guard.cause(), StopCause::output_limit);
  const std::string& csv = rows.csv();
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), TimeseriesRecorder<2>::kMaxRows + 1);  // and the header
}

// Minimisations that never converge (steps of 1e-9: the overlaps stay) and may iterate
// 10^8 times: the wall-clock limit cuts
// the step they are in (its groups go to the fall-back, as at max_iterations), and the run
// ends with its files.
TEST(Stopping, WallClockCutsATimeStepThatDoesNotEnd) {
  TempDir tmp;
  const fs::path run = tmp / "run";
  const testing::Outcome o = run_ballagg(
      run_args(run, {"engine.kind=\"ts\"", "system.n=400", "system.volume_fraction=0.4", "ts.max_iterations=100000000",
                     "ts.stall_iterations=0", "ts.delta=1e-9", "ts.eps_c=1e-12", "ts.max_link_rounds=1000000",
                     "stop.wall_seconds=0.5"}),
      tmp.path());
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(stop_reason(run), "wall_seconds");
  EXPECT_TRUE(fs::exists(run / "final.csv"));
}

// ---- signals ------------------------------------------------------------------------------

// A closed terminal (SIGHUP) stops a run as SIGTERM does: a checkpoint, how to resume,
// status 128 + 1.
TEST(Stopping, SighupWritesACheckpointAndSaysHowToResume) {
  TempDir tmp;
  const fs::path run = tmp / "run";
  const pid_t pid = start_run(run_args(run, {"system.n=30000", "output.checkpoint_every=0"}), run, tmp / "log", 100);
  kill(pid, SIGHUP);
  const int status = exit_status(pid);
  const std::string log = slurp(tmp / "log");
  if (fs::exists(run / "summary.json")) GTEST_SKIP() << "finished before the signal";
  EXPECT_EQ(status, 128 + SIGHUP) << log;
  EXPECT_CONTAINS(log, "interrupted by SIGHUP");
  EXPECT_CONTAINS(log, "ballagg run --resume " + run.string());
  EXPECT_TRUE(fs::exists(run / kCheckpointFile));
}

// The arguments of a run with both trajectories whose checkpoint takes a while to write.
std::vector<std::string> run_with_trajectories(const fs::path& run) {
  return run_args(run, {"system.n=100000", "output.checkpoint_every=0", "output.snapshot_every=0.05",
                        "output.snapshot_formats=[\"h5md\", \"xyz\"]"});
}

// A second SIGINT while the checkpoint is being written quits when it is complete: no
// temporary file is left but the trajectories the checkpoint refers to, and the run
// resumes.
TEST(Stopping, SecondSigintDuringTheCheckpointLeavesNoTemporaryFile) {
  TempDir tmp;
  const fs::path run = tmp / "run";
  const pid_t pid = start_run(run_with_trajectories(run), run, tmp / "log", 300);
  kill(pid, SIGINT);
  const bool writing = wait_until([&] { return fs::exists(run / ".checkpoint.bin.tmp"); }, 30.0);
  kill(pid, SIGINT);
  const int status = exit_status(pid);
  ASSERT_TRUE(writing) << slurp(tmp / "log");
  EXPECT_EQ(status, 128 + SIGINT) << slurp(tmp / "log");
  ASSERT_TRUE(fs::exists(run / kCheckpointFile)) << slurp(tmp / "log");
  for (const std::string& name : temporaries(run))
    EXPECT_TRUE(name == ".trajectory.h5md.tmp" || name == ".trajectory.xyz.tmp") << name;
  EXPECT_EQ(read_checkpoint_file(run.string()).engine, "ed");  // whole: it reads back
}

// SIGINT after SIGINT, as a user hammering Ctrl-C: the second quits at once, and removes
// the temporary files no checkpoint refers to (or, during the checkpoint write, quits
// once the checkpoint is in place).
TEST(Stopping, RepeatedSigintsLeaveNoTemporaryFile) {
  TempDir tmp;
  const fs::path run = tmp / "run";
  const pid_t pid = start_run(run_with_trajectories(run), run, tmp / "log", 300);
  int status = -1;
  for (int k = 0; k < 1000 && status < 0; ++k) {
    kill(pid, SIGINT);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    int raw = 0;
    if (waitpid(pid, &raw, WNOHANG) == pid) status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  }
  if (status < 0) status = exit_status(pid, 10.0);
  EXPECT_EQ(status, 128 + SIGINT) << slurp(tmp / "log");
  if (fs::exists(run / kCheckpointFile)) {
    for (const std::string& name : temporaries(run))
      EXPECT_TRUE(name == ".trajectory.h5md.tmp" || name == ".trajectory.xyz.tmp") << name;
  } else {
    EXPECT_TRUE(temporaries(run).empty()) << temporaries(run).front();
  }
}

// SIGINT during a sweep: the run under way stops and leaves nothing, the tables of the
// runs done are written, the sweep says how to resume; resumed, it finishes.
TEST(Stopping, InterruptedSweepSaysHowToResumeAndWritesTables) {
  TempDir tmp;
  const fs::path file = tmp.write("s.toml", "[sweep]\nrealizations = 3\n[grid]\nsystem.n = [3000]\n");
  const fs::path out = tmp / "out";
  const std::vector<std::string> args{"sweep", file.string(), "--out", out.string(), "--jobs", "1"};
  const pid_t pid = start_ballagg(args, tmp / "log");
  const bool one_done = wait_until([&] { return slurp(tmp / "log").find(" done\n") != std::string::npos; }, 60.0);
  kill(pid, SIGINT);
  const int status = exit_status(pid);
  const std::string log = slurp(tmp / "log");
  ASSERT_TRUE(one_done) << log;
  if (status == 0) GTEST_SKIP() << "finished before the signal";
  EXPECT_EQ(status, 128 + SIGINT) << log;
  EXPECT_CONTAINS(log, "ballagg: sweep interrupted by SIGINT: ");
  EXPECT_CONTAINS(log, " of 3 runs done");
  EXPECT_CONTAINS(log, "continue with: ballagg sweep " + file.string() + " --out " + out.string() + " --resume");
  ASSERT_TRUE(fs::exists(out / "sweep.csv"));
  const std::string runs = slurp(out / "runs.csv");
  EXPECT_GE(std::count(runs.begin(), runs.end(), '\n'), 2) << runs;  // the header and a run done
  for (const auto& e : fs::directory_iterator(out / "runs"))  // the run under way left nothing
    EXPECT_TRUE(fs::exists(e.path() / "summary.json")) << e.path();
  std::vector<std::string> resume = args;
  resume.push_back("--resume");
  const testing::Outcome resumed = run_ballagg(resume, tmp.path());
  EXPECT_EQ(resumed.status, 0) << resumed.err;
  const std::string all = slurp(out / "runs.csv");
  EXPECT_EQ(std::count(all.begin(), all.end(), '\n'), 4) << all;
}

}  // namespace
}  // namespace ballagg
