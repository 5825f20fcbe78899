// Trajectory frames: taken at exact simulated times without changing the run, equal to
// the state a run stopped at that time ends in, clusters in one piece across periodic
// faces, byte-identical files from run to run (the files themselves: tests/io/test_h5md.cpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <hdf5.h>

#include "ballagg/engines/time_stepping/time_stepping_engine.hpp"
#include "ballagg/io/background_writer.hpp"
#include "ballagg/io/h5md_reader.hpp"
#include "ballagg/io/h5md_writer.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/xyz_trajectory_writer.hpp"
#include "ballagg/run/snapshots.hpp"
#include "cli_support.hpp"
#include "frames.hpp"
#include "support.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {

using testing::small_config;
using testing::TempDir;
using testing::expect_same_frame;
using testing::MemorySink;
using testing::Recorded;
using testing::run_with_snapshots;

TEST(Snapshots, FramesAreAtZeroAtEveryMultipleOfTheIntervalAndAtTheEnd) {
  const Config c = small_config(2, 200, 0.2, Boundary::periodic, 3);
  const Recorded<2> r = run_with_snapshots<2>(c, 0.75);
  const double end = r.final_state.time;
  ASSERT_GT(end, 3.0);
  const int multiples = static_cast<int>(std::floor(end / 0.75));
  ASSERT_EQ(static_cast<int>(r.frames.size()), multiples + 2);
  for (int k = 0; k <= multiples; ++k) EXPECT_EQ(r.frames[k].time, k * 0.75) << "frame " << k;
  EXPECT_EQ(r.frames.back().time, end);
  for (std::size_t k = 1; k < r.frames.size(); ++k) EXPECT_GE(r.frames[k].step, r.frames[k - 1].step);
  EXPECT_EQ(r.frames.back().n_clusters, 1);
}

TEST(Snapshots, SnapshotsDoNotChangeTheRun) {
  const Config c = small_config(2, 300, 0.2, Boundary::walls, 4);
  State<2> plain = make_initial_state<2>(c);
  RunObserver<2> none;
  const RunResult without = make_engine<2>(resolve_defaults(c, plain))->run(plain, {}, none);
  const Recorded<2> with = run_with_snapshots<2>(c, 0.5);
  EXPECT_EQ(with.result.counters.events, without.counters.events);
  EXPECT_EQ(with.final_state.time, plain.time);
  expect_same_frame(capture_frame(with.final_state, with.final_state.time, 0),
                    capture_frame(plain, plain.time, 0));
}

// Positions are lazy, so the frame at t = k * every is the state a run stopped at that
// time ends in, bit for bit (event-driven engines: nothing happens between events).
template <int D>
void frame_equals_run_stopped_at_its_time(Boundary boundary) {
  const Config c = small_config(D, 150, 0.15, boundary, 5);
  const Recorded<D> full = run_with_snapshots<D>(c, 1.25);
  ASSERT_GE(full.frames.size(), 5u);
  State<D> s = make_initial_state<D>(c);
  StopCriteria stop;
  stop.time = 3 * 1.25;
  RunObserver<D> none;
  make_engine<D>(resolve_defaults(c, s))->run(s, stop, none);
  ASSERT_EQ(s.time, full.frames[3].time);
  expect_same_frame(full.frames[3], capture_frame(s, s.time, 0));
}

TEST(Snapshots, FrameEqualsTheRunStoppedAtItsTime2DWalls) { frame_equals_run_stopped_at_its_time<2>(Boundary::walls); }
TEST(Snapshots, FrameEqualsTheRunStoppedAtItsTime3DPeriodic) {
  frame_equals_run_stopped_at_its_time<3>(Boundary::periodic);
}

TEST(Snapshots, LastFrameIsTheFinalState) {
  const Config c = small_config(3, 120, 0.1, Boundary::walls, 6);
  const Recorded<3> r = run_with_snapshots<3>(c, 2.0);
  expect_same_frame(r.frames.back(), capture_frame(r.final_state, r.final_state.time, 0));
}

// With images, position + image * L puts a cluster in one piece: two touching spheres of
// one cluster are at contact distance in unwrapped coordinates too, not a box length apart.
TEST(Snapshots, ImagesPutEveryClusterInOnePieceAcrossPeriodicFaces) {
  const Config c = small_config(2, 400, 0.3, Boundary::periodic, 7);
  const Recorded<2> r = run_with_snapshots<2>(c, 5.0);
  const Frame<2>& f = r.frames.back();
  const double l = r.final_state.box.length;
  int across_faces = 0, contacts = 0;
  for (int i = 0; i < f.size(); ++i) {
    for (int j = i + 1; j < f.size(); ++j) {
      const double d = r.final_state.box.separation(f.position[i], f.position[j]).norm();
      if (f.cluster[i] != f.cluster[j] || d > 1.0 + 1e-9) continue;  // touching spheres of one cluster (R = 0.5)
      ++contacts;
      if ((f.position[i] - f.position[j]).norm() > 0.5 * l) ++across_faces;
      EXPECT_NEAR((f.unwrapped(i, l) - f.unwrapped(j, l)).norm(), d, 1e-9);
    }
  }
  EXPECT_GT(across_faces, 0) << "no contact straddles a face: the test shows nothing";
  EXPECT_GT(contacts, 300);
}

// The time-stepping engine's walls act at the end of a step; a frame between two steps
// shows the free flight mirrored at the walls, so every sphere is inside the box.
TEST(Snapshots, TimeSteppingFramesBetweenStepsLieInsideTheWalls) {
  Config c = small_config(2, 200, 0.25, Boundary::walls, 8);
  c.engine.kind = EngineKind::ts;
  StopCriteria stop;
  stop.time = 3.0;
  auto spheres_outside = [](const Recorded<2>& r) {
    const double l = r.final_state.box.length;
    int outside = 0;
    for (const Frame<2>& f : r.frames)
      for (int i = 0; i < f.size(); ++i)
        for (int a = 0; a < 2; ++a) outside += f.position[i][a] < 0.5 - 1e-9 || f.position[i][a] > l - 0.5 + 1e-9;
    return outside;
  };
  const Recorded<2> r = run_with_snapshots<2>(c, 0.05, stop);
  ASSERT_EQ(r.frames.size(), 61u);
  for (std::size_t k = 0; k < r.frames.size(); ++k) EXPECT_DOUBLE_EQ(r.frames[k].time, static_cast<double>(k) * 0.05);
  EXPECT_EQ(spheres_outside(r), 0);
  // The premise: plain free flight does cross the walls between two steps.
  EXPECT_GT(spheres_outside(run_with_snapshots<2>(c, 0.05, stop, false)), 0);
}

// Rigid-body runs: clusters rotate, and the engine writes the rotated sphere offsets only
// when an observer reads them (RunObserver::next_position_read). Each frame is then the
// state of a run stopped at its time, and the velocity of each sphere is the time
// derivative of its position, V + omega x (x - X_c), not its cluster's velocity.
class RigidBodySnapshots : public ::testing::Test {
 protected:
  static constexpr double kEvery = 1e-4;
  void SetUp() override {
    c_ = small_config(3, 150, 0.15, Boundary::periodic, 5);
    c_.engine.kind = EngineKind::rigid_body;
    c_.initial.velocities = InitialVelocities::gaussian;
    start_ = make_initial_state<3>(c_);
    c_ = resolve_defaults(c_, start_);
    StopCriteria grow;
    grow.clusters = 100;  // spinning aggregates first
    RunObserver<3> none;
    make_engine<3>(c_)->run(start_, grow, none);
  }
  // Frames every kEvery for 40 intervals from the grown state.
  std::vector<Frame<3>> frames() const {
    State<3> s = start_;
    auto kept = std::make_shared<std::vector<Frame<3>>>();
    std::vector<std::unique_ptr<FrameSink<3>>> sinks;
    sinks.push_back(std::make_unique<MemorySink<3>>(kept));
    SnapshotRecorder<3> recorder(kEvery, std::move(sinks), false);
    StopCriteria stop;
    stop.time = s.time + 40 * kEvery;
    make_engine<3>(c_)->run(s, stop, recorder);
    return *kept;
  }
  Config c_;
  State<3> start_;
};

TEST_F(RigidBodySnapshots, FrameEqualsTheRunStoppedAtItsTime) {
  const std::vector<Frame<3>> f = frames();
  ASSERT_GE(f.size(), 30u);
  const Frame<3>& frame = f[20];
  State<3> s = start_;
  StopCriteria stop;
  stop.time = frame.time;
  RunObserver<3> none;
  make_engine<3>(c_)->run(s, stop, none);
  ASSERT_EQ(s.time, frame.time);
  const Frame<3> stopped = capture_frame(s, s.time, 0);
  EXPECT_EQ(frame.cluster, stopped.cluster);
  double position = 0.0, velocity = 0.0;
  for (int i = 0; i < frame.size(); ++i) {
    position = std::max(position, s.box.separation(frame.position[i], stopped.position[i]).norm());
    velocity = std::max(velocity, (frame.velocity[i] - stopped.velocity[i]).norm());
  }
  EXPECT_LT(position, 1e-12);
  EXPECT_LT(velocity, 1e-12);
}

TEST_F(RigidBodySnapshots, SphereVelocityIsTheDerivativeOfItsPosition) {
  const std::vector<Frame<3>> f = frames();
  const double l = start_.box.length;
  double worst = 0.0, rotation = 0.0;
  int checked = 0;
  for (std::size_t k = 1; k + 1 < f.size(); ++k) {
    if (f[k - 1].n_clusters != f[k + 1].n_clusters) continue;  // a merge in between
    // The first frame is the start, the last the stop: not on the grid of multiples.
    const double before = f[k].time - f[k - 1].time, after = f[k + 1].time - f[k].time;
    if (std::abs(before - after) > 1e-3 * kEvery) continue;
    for (int i = 0; i < f[k].size(); ++i) {
      const Vec<3> rate = (f[k + 1].unwrapped(i, l) - f[k - 1].unwrapped(i, l)) / (before + after);
      worst = std::max(worst, (rate - f[k].velocity[i]).norm());
      const int c = f[k].cluster[i];
      for (int j = 0; j < f[k].size(); ++j)  // another sphere of the same cluster
        if (j != i && f[k].cluster[j] == c) rotation = std::max(rotation, (f[k].velocity[j] - f[k].velocity[i]).norm());
    }
    ++checked;
  }
  ASSERT_GT(checked, 20);
  EXPECT_GT(rotation, 0.1) << "no aggregate spins: the test shows nothing";
  EXPECT_LT(worst, 1e-6);  // central difference: O(kEvery^2 omega^3 r)
}

// Trajectory frames share the copy of a sphere layout (offsets and cluster ids) while
// State::layout_version stays the same, so every change of an offset or a cluster id must
// change the version. Watched at every event of a run: an unchanged version with changed
// offsets or ids is a failure. The rigid-body engine is asked for its rotated offsets often.
template <int D>
class LayoutWatch final : public RunObserver<D> {
 public:
  explicit LayoutWatch(double read_every) : every_(read_every), next_(read_every) {}
  void on_start(const State<D>& s) override { check(s); }
  void before_event(const State<D>& s, double t) override {
    check(s);
    while (next_ < t) next_ += every_;
  }
  void after_event(const State<D>& s, const EventRecord&, const EngineCounters&) override { check(s); }
  void on_finish(const State<D>& s, const RunResult&) override { check(s); }
  double next_position_read() const override { return next_; }

  int versions = 0, unchanged = 0, failures = 0;

 private:
  void check(const State<D>& s) {
    const std::uint64_t v = s.layout_version();
    if (v != version_) {
      version_ = v;
      offset_ = s.spheres.offset;
      cluster_ = s.spheres.cluster;
      ++versions;
    } else if (s.spheres.offset != offset_ || s.spheres.cluster != cluster_) {
      ++failures;
    } else {
      ++unchanged;
    }
  }
  double every_, next_;
  std::uint64_t version_ = 0;
  std::vector<Vec<D>> offset_;
  std::vector<std::int32_t> cluster_;
};

template <int D>
void layout_version_follows_every_change(Config c, const std::string& what) {
  State<D> s = make_initial_state<D>(c);
  c = resolve_defaults(c, s);
  LayoutWatch<D> watch(0.05);
  StopCriteria stop;
  stop.time = 6.0;
  make_engine<D>(c)->run(s, stop, watch);
  EXPECT_EQ(watch.failures, 0) << what;
  EXPECT_GT(watch.versions, 10) << what << ": the layout hardly changed, the test shows little";
  EXPECT_GT(watch.unchanged, 10) << what;
}

TEST(Snapshots, EveryChangeOfTheSphereLayoutChangesItsVersion) {
  Config c = small_config(2, 150, 0.25, Boundary::walls, 13);
  layout_version_follows_every_change<2>(c, "ed 2D walls");
  c.engine.kind = EngineKind::ed_naive;
  layout_version_follows_every_change<2>(c, "ed-naive");
  c.engine.kind = EngineKind::ts;
  for (const TsModel model : {TsModel::rigid, TsModel::almost_rigid, TsModel::non_rigid}) {
    c.ts.model = model;
    layout_version_follows_every_change<2>(c, fmt::format("ts {}", to_string(model)));
  }
  Config p = small_config(3, 150, 0.2, Boundary::periodic, 14);
  layout_version_follows_every_change<3>(p, "ed 3D periodic");
  p.engine.kind = EngineKind::rigid_body;
  p.initial.velocities = InitialVelocities::gaussian;
  layout_version_follows_every_change<3>(p, "rigid-body");
  p.rigid_body.fragmentation_energy = 1e-3;
  layout_version_follows_every_change<3>(p, "rigid-body with fragmentation");
  p.rigid_body.fragmentation_energy.reset();
  p.rigid_body.coagulation = Coagulation::sphere;
  layout_version_follows_every_change<3>(p, "rigid-body, sphere coagulation");
}

// Assembling a frame block by block (any block sizes) gives the frame assemble_frame gives,
// cluster labels included (they continue from block to block).
TEST(Snapshots, FrameAssembledInBlocksIsTheWholeFrame) {
  const Config c = small_config(2, 300, 0.3, Boundary::periodic, 11);
  State<2> s = make_initial_state<2>(c);
  StopCriteria stop;
  stop.clusters = 40;
  RunObserver<2> none;
  make_engine<2>(resolve_defaults(c, s))->run(s, stop, none);
  FrameSource<2> source;
  LayoutCopies<2> layouts;
  capture_source(s, s.time, 7, false, source, layouts);
  Frame<2> whole;
  assemble_frame(source, whole);
  ASSERT_GT(*std::max_element(whole.cluster.begin(), whole.cluster.end()), 30);
  std::vector<double> position(2 * 300), velocity(2 * 300);
  std::vector<std::int32_t> image(2 * 300), cluster(300);
  FrameAssembler<2> assembler;
  assembler.start(source);
  for (int begin = 0, size = 1; begin < 300; begin += size, size = size * 2 % 97 + 1) {
    const int end = std::min(300, begin + size);
    assembler.assemble(begin, end, &position[2 * begin], &velocity[2 * begin], &image[2 * begin], &cluster[begin]);
  }
  EXPECT_EQ(cluster, whole.cluster);
  for (int i = 0; i < 300; ++i) {
    EXPECT_EQ(Vec<2>(position[2 * i], position[2 * i + 1]), whole.position[i]) << i;
    EXPECT_EQ(Vec<2>(velocity[2 * i], velocity[2 * i + 1]), whole.velocity[i]) << i;
    EXPECT_EQ(Image<2>(image[2 * i], image[2 * i + 1]), whole.image[i]) << i;
  }
  EXPECT_THROW(assembler.assemble(0, 1, position.data(), velocity.data(), image.data(), cluster.data()), std::logic_error);
}

// The whole chain through the command line: files written, complete, the same bytes twice.
TEST(SnapshotsCli, TrajectoriesAreByteIdenticalFromRunToRun) {
  const TempDir dir;
  std::string h5md, xyz, h5md_double;
  for (const char* name : {"a", "b"}) {
    const testing::Outcome o = testing::run_ballagg(
        {"run", "-q", "--out", (dir / name).string(), "--set", "system.n=200", "--set", "system.boundary=periodic",
         "--set", "output.snapshot_every=2", "--set", "output.snapshot_formats=[\"h5md\", \"xyz\"]"},
        dir.path());
    const std::string doubles = std::string(name) + "-double";
    const testing::Outcome d = testing::run_ballagg(
        {"run", "-q", "--out", (dir / doubles).string(), "--set", "system.n=200", "--set", "system.boundary=periodic",
         "--set", "output.snapshot_every=2", "--set", "output.snapshot_precision=double"},
        dir.path());
    ASSERT_EQ(d.status, 0) << d.err;
    if (h5md_double.empty()) h5md_double = testing::slurp(dir / doubles / "trajectory.h5md");
    else EXPECT_TRUE(h5md_double == testing::slurp(dir / doubles / "trajectory.h5md"));
    ASSERT_EQ(o.status, 0) << o.err;
    for (const auto& e : fs::directory_iterator(dir / name))
      EXPECT_NE(e.path().filename().string().front(), '.') << e.path();  // no temporary left
    if (h5md.empty()) {
      h5md = testing::slurp(dir / name / "trajectory.h5md");
      xyz = testing::slurp(dir / name / "trajectory.xyz");
      continue;
    }
    EXPECT_TRUE(h5md == testing::slurp(dir / name / "trajectory.h5md"));
    EXPECT_TRUE(xyz == testing::slurp(dir / name / "trajectory.xyz"));
  }
  EXPECT_GT(h5md.size(), 1000u);
  EXPECT_GT(h5md_double.size(), h5md.size());  // positions and velocities: doubles instead of floats
}

TEST(SnapshotsCli, NoTrajectoryUnlessAsked) {
  const TempDir dir;
  ASSERT_EQ(testing::run_ballagg({"run", "-q", "--out", (dir / "r").string(), "--set", "system.n=16"}, dir.path()).status, 0);
  EXPECT_FALSE(fs::exists(dir / "r" / "trajectory.h5md"));
  EXPECT_FALSE(fs::exists(dir / "r" / "trajectory.xyz"));
}

}  // namespace
}  // namespace ballagg
