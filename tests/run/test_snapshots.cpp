// Trajectory frames: taken at exact simulated times without changing the run, equal to
// the state a run stopped at that time ends in, clusters in one piece across periodic
// faces, and written to H5MD and extended XYZ files that read back to the same numbers
// and are byte-identical from run to run.
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

// What a single-precision file holds: positions and velocities rounded to the nearest float.
// The rounding is a function of its own: g++ 12.2 at -O2 vectorizes x[a] = (double)(float)x[a]
// over the components of a vector into nothing (the values stay unrounded), and with it
// this test would compare the file against unrounded values.
[[gnu::noinline]] float to_float(double x) { return static_cast<float>(x); }

template <int D>
Frame<D> rounded_to_float(Frame<D> f) {
  for (std::vector<Vec<D>>* values : {&f.position, &f.velocity})
    for (Vec<D>& x : *values)
      for (int a = 0; a < D; ++a) x[a] = to_float(x[a]);
  return f;
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
  p.collision.fragmentation_energy = 1e-3;
  layout_version_follows_every_change<3>(p, "rigid-body with fragmentation");
  p.collision.fragmentation_energy.reset();
  p.collision.coagulation = Coagulation::sphere;
  layout_version_follows_every_change<3>(p, "rigid-body, sphere coagulation");
}

template <int D>
void h5md_round_trip(Boundary boundary, SnapshotPrecision precision) {
  const Config c = small_config(D, 90, 0.15, boundary, 9);
  const Recorded<D> r = run_with_snapshots<D>(c, 1.0);
  const TempDir dir;
  const std::string path = (dir / "t.h5md").string();
  {
    H5mdWriter<D> writer(path, particles_of(r.final_state), to_toml_text(c), precision);
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
  bool rounded = false;  // single precision changes some value (else the test shows nothing)
  for (int k = 0; k < reader.frames(); ++k) {
    const Frame<D> f = reader.frame(k);
    if (precision == SnapshotPrecision::single) {
      expect_same_frame(f, rounded_to_float(r.frames[k]));
      for (int i = 0; i < f.size(); ++i) rounded = rounded || f.position[i] != r.frames[k].position[i];
    } else {
      expect_same_frame(f, r.frames[k]);
    }
    EXPECT_EQ(f.step, r.frames[k].step);
    EXPECT_EQ(f.n_clusters, r.frames[k].n_clusters);
    EXPECT_EQ(f.largest_cluster, r.frames[k].largest_cluster);
    EXPECT_EQ(f.kinetic_energy, r.frames[k].kinetic_energy);
  }
  EXPECT_EQ(rounded, precision == SnapshotPrecision::single);
  EXPECT_THROW(reader.frame(reader.frames()), InputError);
}

TEST(H5md, RoundTripIsExact2DPeriodic) { h5md_round_trip<2>(Boundary::periodic, SnapshotPrecision::double_); }
TEST(H5md, RoundTripIsExact3DWalls) { h5md_round_trip<3>(Boundary::walls, SnapshotPrecision::double_); }
TEST(H5md, SinglePrecisionRoundTripIsTheFrameRoundedToFloat2DPeriodic) {
  h5md_round_trip<2>(Boundary::periodic, SnapshotPrecision::single);
}
TEST(H5md, SinglePrecisionRoundTripIsTheFrameRoundedToFloat3DWalls) {
  h5md_round_trip<3>(Boundary::walls, SnapshotPrecision::single);
}

// The stored type of a dataset of the file: (class, bytes per value).
std::pair<H5T_class_t, std::size_t> stored_type(const std::string& path, const std::string& dataset) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  const hid_t type = H5Dget_type(d);
  const std::pair<H5T_class_t, std::size_t> result{H5Tget_class(type), H5Tget_size(type)};
  H5Tclose(type);
  H5Dclose(d);
  H5Fclose(file);
  return result;
}

TEST(H5md, PrecisionIsTheStoredTypeOfPositionsAndVelocitiesOnly) {
  const State<2> s = make_initial_state<2>(small_config(2, 50, 0.1, Boundary::periodic, 1));
  const TempDir dir;
  for (const SnapshotPrecision precision : {SnapshotPrecision::single, SnapshotPrecision::double_}) {
    const std::string path = (dir / fmt::format("{}.h5md", to_string(precision))).string();
    H5mdWriter<2> writer(path, particles_of(s), "", precision);
    writer.write(capture_frame(s, 0.0, 0));
    writer.finish();
    const std::size_t bytes = precision == SnapshotPrecision::single ? 4 : 8;
    for (const char* d : {"particles/all/position/value", "particles/all/velocity/value"})
      EXPECT_EQ(stored_type(path, d), std::make_pair(H5T_FLOAT, bytes)) << d;
    for (const char* d : {"particles/all/radius", "particles/all/mass", "particles/all/position/time",
                          "observables/kinetic_energy/value", "particles/all/box/edges"})
      EXPECT_EQ(stored_type(path, d), std::make_pair(H5T_FLOAT, std::size_t{8})) << d;
    for (const char* d : {"particles/all/cluster/value", "particles/all/image/value"})
      EXPECT_EQ(stored_type(path, d), std::make_pair(H5T_INTEGER, std::size_t{4})) << d;
  }
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

// The writer thread hands H5mdWriter the frame's source, which it assembles block by block;
// the file is the one written from the assembled frame, byte for byte, in both precisions
// and over several blocks (70001 spheres: two blocks, one of them a sphere shorter).
TEST(H5md, FramesWrittenFromTheirSourceAreTheFileOfTheAssembledFrames) {
  const Config c = small_config(2, 70001, 0.2, Boundary::periodic, 12);
  const State<2> s = make_initial_state<2>(c);
  const TempDir dir;
  std::vector<FrameSource<2>> sources(3);
  LayoutCopies<2> layouts;
  for (int k = 0; k < 3; ++k) capture_source(s, 2.0 * k, k, false, sources[k], layouts);
  for (const SnapshotPrecision precision : {SnapshotPrecision::single, SnapshotPrecision::double_}) {
    const std::string from_frames = (dir / "frames.h5md").string(), from_sources = (dir / "sources.h5md").string();
    H5mdWriter<2> a(from_frames, particles_of(s), "", precision), b(from_sources, particles_of(s), "", precision);
    std::vector<Frame<2>> frames(3);
    for (int k = 0; k < 3; ++k) {
      assemble_frame(sources[k], frames[k]);
      a.write(frames[k]);
      b.write_source(sources[k], [&]() -> const Frame<2>& { ADD_FAILURE() << "assembled a whole frame"; return frames[k]; });
    }
    a.finish();
    b.finish();
    EXPECT_TRUE(testing::slurp(from_frames) == testing::slurp(from_sources)) << to_string(precision);
    const H5mdReader<2> reader(from_sources);
    ASSERT_EQ(reader.frames(), 3);
    const Frame<2> last = reader.frame(2);
    expect_same_frame(last, precision == SnapshotPrecision::single ? rounded_to_float(frames[2]) : frames[2]);
    EXPECT_GT(std::count_if(last.image.begin(), last.image.end(), [](const Image<2>& i) { return !i.isZero(); }), 0);
  }
}

TEST(H5md, AResumedTrajectoryKeepsItsPrecision) {
  const State<2> s = make_initial_state<2>(small_config(2, 20, 0.1, Boundary::walls, 1));
  const TempDir dir;
  const std::string path = (dir / "t.h5md").string();
  std::uint64_t mark = 0;
  {
    H5mdWriter<2> writer(path, particles_of(s), "", SnapshotPrecision::single);
    writer.write(capture_frame(s, 0.0, 0));
    mark = writer.flush();  // a checkpoint: the temporary file stays
  }
  ASSERT_EQ(mark, 1u);
  try {
    H5mdWriter<2> other(path, particles_of(s), mark, SnapshotPrecision::double_);
    FAIL() << "a single-precision trajectory continued in double precision";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "cannot continue the trajectory");
  }
  {
    H5mdWriter<2> same(path, particles_of(s), mark, SnapshotPrecision::single);
    same.write(capture_frame(s, 1.0, 1));
    same.finish();
  }
  const H5mdReader<2> reader(path);
  ASSERT_EQ(reader.frames(), 2);
  expect_same_frame(reader.frame(1), rounded_to_float(capture_frame(s, 1.0, 1)));
}

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

// A sink whose writes wait until the test opens it, recording the frames' times.
class GatedSink final : public FrameSink<2> {
 public:
  struct Gate {
    std::mutex mutex;
    std::condition_variable opened;
    bool open = false;
    std::vector<double> times;
    void let_through() {
      {
        std::lock_guard lock(mutex);
        open = true;
      }
      opened.notify_all();
    }
  };
  explicit GatedSink(std::shared_ptr<Gate> gate) : gate_(std::move(gate)) {}
  void write(const Frame<2>& f) override {
    std::unique_lock lock(gate_->mutex);
    gate_->opened.wait(lock, [&] { return gate_->open; });
    gate_->times.push_back(f.time);
  }
  void finish() override {}
  std::uint64_t flush() override { return 0; }

 private:
  std::shared_ptr<Gate> gate_;
};

// Frames queued through a writer with `budget` bytes while its sink holds the first one
// back until `held` frames are queued; returns how many sources the writer allocated.
int sources_for_frames(std::size_t budget, int frames, int held, const std::shared_ptr<GatedSink::Gate>& gate) {
  const State<2> s = make_initial_state<2>(small_config(2, 100, 0.1, Boundary::walls, 1));
  std::vector<std::unique_ptr<FrameSink<2>>> sinks;
  sinks.push_back(std::make_unique<GatedSink>(gate));
  BackgroundWriter<2> writer(std::move(sinks), budget);
  LayoutCopies<2> layouts;
  for (int k = 0; k < frames; ++k) {
    if (k == held) gate->let_through();
    capture_source(s, k, k, false, writer.acquire(), layouts);
    writer.submit();
  }
  gate->let_through();
  writer.finish();
  return writer.sources();
}

TEST(BackgroundWriter, SmallFramesQueueUpToTheMemoryBudgetWithoutWaiting) {
  // 100 frames of 100 discs (a few kB each) fit in 1 MB: all are queued while the sink
  // holds the first back; the run never waits for it.
  auto gate = std::make_shared<GatedSink::Gate>();
  EXPECT_EQ(sources_for_frames(1 << 20, 100, 100, gate), 100);
  ASSERT_EQ(gate->times.size(), 100u);
  for (int k = 0; k < 100; ++k) EXPECT_EQ(gate->times[k], k);
}

TEST(BackgroundWriter, FramesLargerThanTheBudgetAreInFlightOneAtATime) {
  auto gate = std::make_shared<GatedSink::Gate>();
  EXPECT_EQ(sources_for_frames(1, 20, 0, gate), 1);
  ASSERT_EQ(gate->times.size(), 20u);
  for (int k = 0; k < 20; ++k) EXPECT_EQ(gate->times[k], k);
}

TEST(BackgroundWriter, TheBudgetBoundsTheFramesInFlight) {
  const State<2> s = make_initial_state<2>(small_config(2, 100, 0.1, Boundary::walls, 1));
  FrameSource<2> probe;
  LayoutCopies<2> layouts;
  capture_source(s, 0.0, 0, false, probe, layouts);
  // Room for three sources: the fourth frame waits for the sink to free one (the gate
  // opens from another thread while the run waits).
  auto gate = std::make_shared<GatedSink::Gate>();
  std::thread opener([gate] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    gate->let_through();
  });
  const int sources = sources_for_frames(3 * probe.bytes(), 30, 30, gate);
  opener.join();
  EXPECT_EQ(sources, 3);
  ASSERT_EQ(gate->times.size(), 30u);
  for (int k = 0; k < 30; ++k) EXPECT_EQ(gate->times[k], k);
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
