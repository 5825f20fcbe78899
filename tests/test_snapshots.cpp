// Trajectory frames: taken at exact simulated times without changing the run, equal to
// the state a run stopped at that time ends in, clusters in one piece across periodic
// faces, and written to H5MD and extended XYZ files that read back to the same numbers
// and are byte-identical from run to run.
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <hdf5.h>

#include "ballagg/engines/time_stepping/time_stepping_engine.hpp"
#include "ballagg/io/h5md_reader.hpp"
#include "ballagg/io/h5md_writer.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/xyz_trajectory_writer.hpp"
#include "ballagg/run/snapshots.hpp"
#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {

using testing::small_config;
using testing::TempDir;

// Keeps every frame in memory (shared with the test, the recorder owns the sink).
template <int D>
class MemorySink final : public FrameSink<D> {
 public:
  explicit MemorySink(std::shared_ptr<std::vector<Frame<D>>> frames) : frames_(std::move(frames)) {}
  void write(const Frame<D>& f) override { frames_->push_back(f); }
  void finish() override { finished = true; }
  std::uint64_t flush() override { return frames_->size(); }
  bool finished = false;

 private:
  std::shared_ptr<std::vector<Frame<D>>> frames_;
};

template <int D>
struct Recorded {
  std::vector<Frame<D>> frames;
  State<D> final_state;
  RunResult result;
};

// Runs `config` with an engine of its kind, frames every `every` kept in memory.
template <int D>
Recorded<D> run_with_snapshots(const Config& given, double every, StopCriteria stop = {},
                               std::optional<bool> mirror_at_walls = std::nullopt) {
  State<D> s = make_initial_state<D>(given);
  const Config c = resolve_defaults(given, s);
  auto frames = std::make_shared<std::vector<Frame<D>>>();
  std::vector<std::unique_ptr<FrameSink<D>>> sinks;
  sinks.push_back(std::make_unique<MemorySink<D>>(frames));
  SnapshotRecorder<D> recorder(every, std::move(sinks), mirror_at_walls.value_or(c.engine.kind == EngineKind::ts));
  Recorded<D> r{{}, {}, make_engine<D>(c)->run(s, stop, recorder)};
  r.frames = *frames;
  r.final_state = s;
  return r;
}

template <int D>
void expect_same_frame(const Frame<D>& a, const Frame<D>& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.cluster, b.cluster);
  EXPECT_EQ(a.image, b.image);
  for (int i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.position[i], b.position[i]) << "sphere " << i;
    EXPECT_EQ(a.velocity[i], b.velocity[i]) << "sphere " << i;
  }
}

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

template <int D>
void h5md_round_trip(Boundary boundary) {
  const Config c = small_config(D, 90, 0.15, boundary, 9);
  const Recorded<D> r = run_with_snapshots<D>(c, 1.0);
  const TempDir dir;
  const std::string path = (dir / "t.h5md").string();
  {
    H5mdWriter<D> writer(path, particles_of(r.final_state), to_toml_text(c));
    for (const Frame<D>& f : r.frames) writer.write(f);
    EXPECT_TRUE(fs::exists(temporary_path_for(path)));
    EXPECT_FALSE(fs::exists(path));  // complete files only
    writer.finish();
  }
  EXPECT_FALSE(fs::exists(temporary_path_for(path)));
  const H5mdReader<D> reader(path);
  ASSERT_EQ(reader.frames(), static_cast<int>(r.frames.size()));
  EXPECT_EQ(reader.particles().radius, r.final_state.spheres.radius);
  EXPECT_EQ(reader.particles().mass, r.final_state.spheres.mass);
  EXPECT_EQ(reader.particles().box.length, r.final_state.box.length);
  EXPECT_EQ(reader.particles().box.boundary, boundary);
  for (int k = 0; k < reader.frames(); ++k) {
    const Frame<D> f = reader.frame(k);
    expect_same_frame(f, r.frames[k]);
    EXPECT_EQ(f.step, r.frames[k].step);
    EXPECT_EQ(f.n_clusters, r.frames[k].n_clusters);
    EXPECT_EQ(f.largest_cluster, r.frames[k].largest_cluster);
    EXPECT_EQ(f.kinetic_energy, r.frames[k].kinetic_energy);
  }
  EXPECT_THROW(reader.frame(reader.frames()), InputError);
}

TEST(H5md, RoundTripIsExact2DPeriodic) { h5md_round_trip<2>(Boundary::periodic); }
TEST(H5md, RoundTripIsExact3DWalls) { h5md_round_trip<3>(Boundary::walls); }

TEST(H5md, AnUnfinishedWriterLeavesNothing) {
  const TempDir dir;
  const std::string path = (dir / "t.h5md").string();
  const State<2> s = make_initial_state<2>(small_config(2, 10, 0.1, Boundary::walls, 1));
  {
    H5mdWriter<2> writer(path, particles_of(s), "");
    writer.write(capture_frame(s, 0.0, 0));
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(H5md, AnErrorOnTheWriterThreadIsAnExceptionNotALibraryTrace) {
  // Frames are written on BackgroundWriter's thread, and HDF5 keeps its error printing
  // switch per thread: a failure there must still reach the user as one line of ours.
  const TempDir dir;
  const State<2> s = make_initial_state<2>(small_config(2, 10, 0.1, Boundary::walls, 1));
  H5mdWriter<2> writer((dir / "t.h5md").string(), particles_of(s), "");
  const Frame<2> frame = capture_frame(s, 0.0, 0);
  // Close the writer's datasets behind its back, so that the next write fails inside HDF5.
  std::vector<hid_t> datasets(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_DATASET));
  H5Fget_obj_ids(H5F_OBJ_ALL, H5F_OBJ_DATASET, datasets.size(), datasets.data());
  ASSERT_FALSE(datasets.empty());
  for (hid_t d : datasets) H5Dclose(d);
  ::testing::internal::CaptureStderr();
  bool threw = false;
  std::thread([&] {
    try {
      writer.write(frame);
    } catch (const std::runtime_error&) {
      threw = true;
    }
  }).join();
  const std::string printed = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(threw);
  EXPECT_EQ(printed, "");
}

TEST(H5md, ReaderRejectsWhatIsNotATrajectory) {
  const TempDir dir;
  EXPECT_THROW(H5mdReader<2>((dir / "missing.h5md").string()), InputError);
  EXPECT_THROW(H5mdReader<2>(dir.write("text.h5md", "not hdf5\n").string()), InputError);
  const State<3> s = make_initial_state<3>(small_config(3, 10, 0.1, Boundary::walls, 1));
  H5mdWriter<3> writer((dir / "t3.h5md").string(), particles_of(s), "");
  writer.write(capture_frame(s, 0.0, 0));
  writer.finish();
  try {
    H5mdReader<2> reader((dir / "t3.h5md").string());
    FAIL() << "a 3D file read as 2D";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "a 3D trajectory");
  }
}

TEST(XyzTrajectory, HasOneFrameOfNPlusTwoLinesPerSnapshot) {
  const Config c = small_config(2, 50, 0.15, Boundary::periodic, 10);
  const Recorded<2> r = run_with_snapshots<2>(c, 2.0);
  const TempDir dir;
  const std::string path = (dir / "t.xyz").string();
  XyzTrajectoryWriter<2> writer(path, particles_of(r.final_state));
  for (const Frame<2>& f : r.frames) writer.write(f);
  writer.finish();
  std::istringstream in(testing::slurp(path));
  std::string line;
  int frames = 0;
  while (std::getline(in, line)) {
    ASSERT_EQ(line, "50");
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_CONTAINS(line, fmt::format("Time={}", r.frames[frames].time));
    EXPECT_CONTAINS(line, "pbc=\"T T F\"");
    for (int i = 0; i < 50; ++i) ASSERT_TRUE(std::getline(in, line));
    ++frames;
  }
  EXPECT_EQ(frames, static_cast<int>(r.frames.size()));
}

// The whole chain through the command line: files written, complete, the same bytes twice.
TEST(SnapshotsCli, TrajectoriesAreByteIdenticalFromRunToRun) {
  const TempDir dir;
  std::string h5md, xyz;
  for (const char* name : {"a", "b"}) {
    const testing::Outcome o = testing::run_ballagg(
        {"run", "-q", "--out", (dir / name).string(), "--set", "system.n=200", "--set", "system.boundary=periodic",
         "--set", "output.snapshot_every=2", "--set", "output.snapshot_formats=[\"h5md\", \"xyz\"]"},
        dir.path());
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
}

TEST(SnapshotsCli, NoTrajectoryUnlessAsked) {
  const TempDir dir;
  ASSERT_EQ(testing::run_ballagg({"run", "-q", "--out", (dir / "r").string(), "--set", "system.n=16"}, dir.path()).status, 0);
  EXPECT_FALSE(fs::exists(dir / "r" / "trajectory.h5md"));
  EXPECT_FALSE(fs::exists(dir / "r" / "trajectory.xyz"));
}

}  // namespace
}  // namespace ballagg
