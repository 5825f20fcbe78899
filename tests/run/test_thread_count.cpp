// The same configuration and seed give byte-identical files on one OpenMP thread and on
// two: every engine's run (final.csv, timeseries.csv, summary.json but for its wall-clock
// fields, final.xyz, and the rigid-body engine's end-of-run analysis) in 2D and 3D, every
// time-stepping cluster model, `ballagg analyze` and `ballagg verify`. Threads only share
// out work whose result does not depend on the sharing: pair scans merged in a fixed
// order, independent per-group solves.
#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/core/parallel.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/run/analyze_run.hpp"
#include "ballagg/run/verify_run.hpp"
#include "ballagg/spatial/pair_scan.hpp"
#include "support.hpp"
#include "thread_count.hpp"

namespace ballagg {
namespace {
using testing::expect_same_files;
using testing::files_of_run;
using testing::on_one_and_two_threads;
using testing::small_config;
using testing::TempDir;

// A run to one cluster (or `clusters`), with extra time-series rows. The parallel loops
// start at a size (kParallelPairScanMin = 20000 spheres for the pair scans of the analysis
// and verification, 4096 for the time-stepping engine's per-sphere loops): the larger
// runs below pass it, in 2D to stay fast.
Config run_config(EngineKind engine, int dimension, int n, Boundary boundary, int clusters = 1,
                  double volume_fraction = 0.15) {
  Config c = small_config(dimension, n, volume_fraction, boundary, 17);
  c.engine.kind = engine;
  c.stop.clusters = clusters;
  c.output.timeseries_interval = 0.5;
  return c;
}

void expect_run_files_independent_of_threads(const Config& c) {
  const TempDir scratch;
  const auto [one, two] = on_one_and_two_threads([&] { return files_of_run(c, scratch); });
  EXPECT_TRUE(one.count("final.csv") && one.count("timeseries.csv") && one.count("summary.json"));
  expect_same_files(one, two);
}

TEST(ThreadCount, EventDrivenRunFilesDoNotDependOnIt) {
  expect_run_files_independent_of_threads(run_config(EngineKind::ed, 2, 400, Boundary::walls));
  expect_run_files_independent_of_threads(run_config(EngineKind::ed, 3, 300, Boundary::periodic));
}

TEST(ThreadCount, NaiveEventDrivenRunFilesDoNotDependOnIt) {
  expect_run_files_independent_of_threads(run_config(EngineKind::ed_naive, 2, 100, Boundary::periodic));
  expect_run_files_independent_of_threads(run_config(EngineKind::ed_naive, 3, 80, Boundary::walls));
}

TEST(ThreadCount, RigidBodyRunFilesDoNotDependOnIt) {
  // Rotating aggregates, and the analysis files written at the end of the run (on 20000
  // spheres, in 2D and 3D: the pair scans run on threads).
  static_assert(20000 >= kParallelPairScanMin);
  Config c = run_config(EngineKind::rigid_body, 3, 150, Boundary::periodic, 10);
  c.initial.velocities = InitialVelocities::gaussian;
  expect_run_files_independent_of_threads(c);
  for (const int dimension : {2, 3}) {
    SCOPED_TRACE(dimension);
    Config walls = run_config(EngineKind::rigid_body, dimension, 20000, Boundary::walls, 19000, 0.1);
    walls.initial.velocities = InitialVelocities::gaussian;
    expect_run_files_independent_of_threads(walls);
  }
}

TEST(ThreadCount, TimeSteppingRunFilesDoNotDependOnIt) {
  // The engine that uses threads most (cell lists, collision groups solved in parallel);
  // test_time_stepping.cpp checks the final state of every cluster model.
  expect_run_files_independent_of_threads(run_config(EngineKind::ts, 2, 300, Boundary::periodic, 30));
  expect_run_files_independent_of_threads(run_config(EngineKind::ts, 2, 5000, Boundary::periodic, 4000, 0.02));
}

// Every group sent to the fall-back (retreat_pairs 1) in long steps of a dense gas: the
// first rounds repair hundreds of groups, in waves shared among the threads
// (repair_waves.hpp), with walls and periodic faces.
TEST(ThreadCount, TimeSteppingRepairsInWavesDoNotDependOnIt) {
  for (const int dimension : {2, 3})
    for (const Boundary boundary : {Boundary::walls, Boundary::periodic}) {
      SCOPED_TRACE(std::to_string(dimension) + "D " + std::string(to_string(boundary)));
      Config c = run_config(EngineKind::ts, dimension, dimension == 2 ? 10000 : 5000, boundary, 1, 0.3);
      c.ts.retreat_pairs = 1;
      c.ts.dt_factor = 0.05;
      c.stop.time = 1.0;
      expect_run_files_independent_of_threads(c);
    }
}

// A dense gas to one cluster in long steps, every group sent to the fall-back: late in the
// run the flight sweeps meet bodies of thousands of spheres, whose searches are shared
// among the threads (kParallelSearchSpheres = 2048 spheres; 22 such searches in this run),
// and rounds apply solutions that move more spheres than one piece of apply() (4096; 21
// such rounds), counted with a print in the engine while writing this test.
TEST(ThreadCount, TimeSteppingSweepsOfLargeBodiesDoNotDependOnIt) {
  Config c = run_config(EngineKind::ts, 2, 10000, Boundary::walls, 1, 0.3);
  c.ts.retreat_pairs = 1;
  c.ts.dt_factor = 0.05;
  expect_run_files_independent_of_threads(c);
}

// One long step (dt_factor 0.05) of a dense gas (Vf 0.3), on enough spheres that every
// parallel loop of a step runs on threads: positions, the near-pair scan, the contact
// checks (kParallelLoopMin spheres) and the solution of the collision groups
// (kParallelPairs = 2000 pairs in a round), checked with a breakpoint on GOMP_parallel
// (docs/hardening.md). The near-pair refresh of later steps (4096 stale spheres) is not
// reached at this size. One test per model and dimension, so that ctest -j shares them.
class ThreadCountTimeStepping : public ::testing::TestWithParam<std::tuple<TsModel, int>> {};
INSTANTIATE_TEST_SUITE_P(EveryModel, ThreadCountTimeStepping,
                         ::testing::Combine(::testing::Values(TsModel::rigid, TsModel::almost_rigid, TsModel::non_rigid),
                                            ::testing::Values(2, 3)),
                         [](const auto& param_info) {
                           std::string name(to_string(std::get<0>(param_info.param)));
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name + "_" + std::to_string(std::get<1>(param_info.param)) + "D";
                         });

TEST_P(ThreadCountTimeStepping, RunFilesDoNotDependOnIt) {
  const TsModel model = std::get<0>(GetParam());
  const int dimension = std::get<1>(GetParam());
  static_assert(5000 >= kParallelLoopMin && 10000 >= kParallelLoopMin);
  Config c = run_config(EngineKind::ts, dimension, dimension == 2 ? 10000 : 5000, Boundary::periodic, 1, 0.3);
  c.ts.model = model;
  c.ts.dt_factor = 0.05;
  c.stop.time = 0.5;
  expect_run_files_independent_of_threads(c);
}

// The team may change between any two parallel regions: the time-stepping engine gives up
// threads while a core is taken and takes them back (core/adaptive_team.hpp). A run
// prepared on one thread whose steps then take two threads and one by turns ends where the
// run on one thread does, bit for bit (and its lists per thread, made for the one thread
// of the start, grow with the team).
TEST(ThreadCount, TimeSteppingRunWhoseTeamChangesEveryStepDoesNotDependOnIt) {
  Config c = run_config(EngineKind::ts, 2, 10000, Boundary::periodic, 1, 0.3);
  c.ts.dt_factor = 0.02;
  c.stop.time = 8.0;
  // At the start of every step: two threads, then one, and so on.
  struct Alternating final : RunObserver<2> {
    bool alternate = false;
    int steps = 0;
    void before_event(const State<2>&, double) override {
      if (alternate) omp_set_num_threads(steps % 2 == 0 ? 2 : 1);
      ++steps;
    }
  };
  auto final_state = [&](bool alternate) {
    const testing::ThreadCount count(1);
    State<2> s = make_initial_state<2>(c);
    const Config resolved = resolve_defaults<2>(c, s);
    Alternating changes;
    changes.alternate = alternate;
    make_engine<2>(resolved)->run(s, stop_criteria(resolved), changes);
    EXPECT_GE(changes.steps, 3);
    std::vector<double> xs;
    for (int i = 0; i < s.n_spheres(); ++i) {
      const Vec<2> x = s.position(i, s.time);
      xs.insert(xs.end(), {x[0], x[1], static_cast<double>(s.spheres.cluster[i])});
    }
    return xs;
  };
  const std::vector<double> one = final_state(false), changing = final_state(true);
  ASSERT_EQ(one.size(), changing.size());
  EXPECT_TRUE(one == changing);
}

TEST(ThreadCount, AnalysisAndVerificationDoNotDependOnIt) {
  // The pair scans (contacts, pair distribution, overlaps) run on threads from 20000
  // spheres on: a state of 20000 spheres in 10000 clusters. `analyze` in 2D (in 3D: the
  // rigid-body run's analysis above), `verify` in 2D and 3D.
  static_assert(20000 >= kParallelPairScanMin);
  for (const int dimension : {2, 3}) {
    SCOPED_TRACE(dimension);
    const TempDir scratch;
    RunOptions options;
    options.out_dir = (scratch / "run").string();
    options.quiet = true;
    options.checkpoint_on_signals = false;
    run_simulation(run_config(EngineKind::ed, dimension, 20000, Boundary::periodic, 10000, 0.2), options);
    if (dimension == 2) {
      const auto [one, two] = on_one_and_two_threads([&] {
        analyze_run({options.out_dir, "", "", (scratch / "analysis").string()});
        auto files = testing::reproducible_files(scratch / "analysis");
        std::filesystem::remove_all(scratch / "analysis");
        return files;
      });
      EXPECT_TRUE(one.count("analysis.json"));
      expect_same_files(one, two);
    }

    const auto [verified_one, verified_two] = on_one_and_two_threads([&] { return verify_run(options.out_dir); });
    EXPECT_GT(verified_one.checks, 0);
    EXPECT_TRUE(verified_one.violations.empty());
    EXPECT_EQ(verified_one.checks, verified_two.checks);
    EXPECT_EQ(verified_one.violations, verified_two.violations);
    EXPECT_EQ(verified_one.notes, verified_two.notes);
  }
}

}  // namespace
}  // namespace ballagg
