// The trajectory files: H5MD written and read back exactly (in double precision) or as the
// frames rounded to float (in single precision), written from the frames' sources on the
// writer thread, refused when incomplete or not a trajectory; the background writer's
// memory budget; the extended-XYZ trajectory.
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

#include "ballagg/io/background_writer.hpp"
#include "ballagg/io/h5md_reader.hpp"
#include "ballagg/io/h5md_writer.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/xyz_trajectory_writer.hpp"
#include "cli_support.hpp"
#include "frames.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

namespace fs = std::filesystem;
using testing::expect_same_frame;
using testing::Recorded;
using testing::run_with_snapshots;
using testing::small_config;
using testing::TempDir;

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

}  // namespace
}  // namespace ballagg
