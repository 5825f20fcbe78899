// The trajectory layouts other tools read: trajectory.gsd (HOOMD-blue's GSD, written by our
// own file-layer writer) and trajectory.h5md stored in 3D for a 2D run. The files are read
// by the tools themselves in tests/io/check_gsd.py and tests/io/check_mdanalysis.py; here, what
// needs no Python: the GSD file layer's structure, a resumed GSD file equal to the
// uninterrupted one byte for byte, and the padded H5MD file read back by ballagg in 2D.
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/config/config.hpp"
#include "ballagg/io/gsd_writer.hpp"
#include "ballagg/io/h5md_reader.hpp"
#include "ballagg/io/h5md_writer.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {

using testing::small_config;
using testing::TempDir;

constexpr int kFrames = 6;

// Frames of the initial state's free flight (positions are lazy: valid at any time), with
// made-up images in a periodic box so that they are not all zero.
template <int D>
std::vector<Frame<D>> flight_frames(const State<D>& s) {
  std::vector<Frame<D>> frames;
  for (int k = 0; k < kFrames; ++k) {
    Frame<D> f = capture_frame(s, s.time + 0.01 * k, 3 * k);
    for (std::size_t i = 0; i < f.image.size(); ++i) f.image[i][0] = static_cast<std::int32_t>(i % 3) - 1;
    frames.push_back(std::move(f));
  }
  return frames;
}

template <class T>
T read_at(const std::string& bytes, std::size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

// A run checkpointed after `checkpoint` frames, killed after writing two more, and resumed:
// its trajectory.gsd is the uninterrupted run's, byte for byte.
template <int D>
void expect_resumed_gsd_is_the_uninterrupted_file(Boundary boundary) {
  const State<D> s = make_initial_state<D>(small_config(D, 40, 0.1, boundary, 5));
  const std::vector<Frame<D>> frames = flight_frames(s);
  const TempDir dir;
  const std::string reference = (dir / "reference.gsd").string(), resumed = (dir / "resumed.gsd").string();
  {
    GsdWriter<D> writer(reference, particles_of(s));
    for (const Frame<D>& f : frames) writer.write(f);
    writer.finish();
  }
  for (int checkpoint = 1; checkpoint + 2 < kFrames; ++checkpoint) {
    std::uint64_t mark = 0;
    {
      GsdWriter<D> writer(resumed, particles_of(s));
      for (int k = 0; k < checkpoint; ++k) writer.write(frames[k]);
      mark = writer.flush();
      for (int k = checkpoint; k < checkpoint + 2; ++k) writer.write(frames[k]);  // lost with the run
    }
    ASSERT_TRUE(fs::exists(temporary_path_for(resumed))) << "a checkpoint refers to the temporary file";
    GsdWriter<D> writer(resumed, particles_of(s), mark);
    for (int k = checkpoint; k < kFrames; ++k) writer.write(frames[k]);
    writer.finish();
    EXPECT_TRUE(testing::slurp(reference) == testing::slurp(resumed)) << "checkpoint after " << checkpoint << " frames";
    fs::remove(resumed);
  }
}

TEST(Gsd, AResumedFileIsTheUninterruptedFile2DPeriodic) { expect_resumed_gsd_is_the_uninterrupted_file<2>(Boundary::periodic); }
TEST(Gsd, AResumedFileIsTheUninterruptedFile3DWalls) { expect_resumed_gsd_is_the_uninterrupted_file<3>(Boundary::walls); }

TEST(Gsd, AResumedRunRefusesATemporaryFileShorterThanItsCheckpoint) {
  const State<2> s = make_initial_state<2>(small_config(2, 40, 0.1, Boundary::walls, 5));
  const TempDir dir;
  const std::string path = (dir / "t.gsd").string();
  {
    GsdWriter<2> writer(path, particles_of(s));
    writer.write(capture_frame(s, 0.0, 0));
    writer.flush();
  }
  EXPECT_THROW(GsdWriter<2>(path, particles_of(s), 2), InputError);
}

// The file layer 2.0 structure that the gsd library checks when it opens a file.
TEST(Gsd, HeaderNameListAndIndexFollowTheFileLayer) {
  const State<3> s = make_initial_state<3>(small_config(3, 30, 0.1, Boundary::periodic, 2));
  const TempDir dir;
  const std::string path = (dir / "t.gsd").string();
  {
    GsdWriter<3> writer(path, particles_of(s));
    for (const Frame<3>& f : flight_frames(s)) writer.write(f);
    writer.finish();
  }
  const std::string bytes = testing::slurp(path);
  ASSERT_GE(bytes.size(), 256u);
  EXPECT_EQ(read_at<std::uint64_t>(bytes, 0), 0x65DF65DF65DF65DFull);
  const auto index_location = read_at<std::uint64_t>(bytes, 8), index_entries = read_at<std::uint64_t>(bytes, 16);
  const auto namelist_location = read_at<std::uint64_t>(bytes, 24), namelist_blocks = read_at<std::uint64_t>(bytes, 32);
  EXPECT_EQ(read_at<std::uint32_t>(bytes, 40), (1u << 16) | 4u);  // hoomd schema 1.4
  EXPECT_EQ(read_at<std::uint32_t>(bytes, 44), 2u << 16);        // file layer 2.0
  EXPECT_EQ(std::string(bytes.data() + 48 + 64), "hoomd");
  EXPECT_EQ(std::string(bytes.data() + 48, 8), "ballagg ");
  ASSERT_EQ(index_location + 32 * index_entries, bytes.size());
  ASSERT_EQ(namelist_location + 64 * namelist_blocks, index_location);
  EXPECT_EQ(bytes[index_location - 1], '\0');
  std::vector<std::string> names;
  for (std::size_t at = namelist_location; bytes[at] != '\0'; at += names.back().size() + 1)
    names.emplace_back(bytes.data() + at);
  EXPECT_EQ(names.size(), 16u);  // with particles/image: a periodic box
  std::uint64_t last_frame = 0, last_id = 0, data_end = 256;
  for (std::uint64_t e = 0; e + 1 < index_entries; ++e) {
    const std::size_t at = index_location + 32 * e;
    const auto frame = read_at<std::uint64_t>(bytes, at), n = read_at<std::uint64_t>(bytes, at + 8);
    const auto location = read_at<std::int64_t>(bytes, at + 16);
    const auto m = read_at<std::uint32_t>(bytes, at + 24);
    const auto id = read_at<std::uint16_t>(bytes, at + 28);
    const auto type = static_cast<std::uint8_t>(bytes[at + 30]);
    EXPECT_TRUE(e == 0 || frame > last_frame || (frame == last_frame && id > last_id)) << "entry " << e;
    EXPECT_EQ(static_cast<std::uint64_t>(location), data_end) << "entry " << e << ": chunks follow each other";
    EXPECT_LT(id, names.size());
    EXPECT_LT(frame, index_entries);
    EXPECT_EQ(bytes[at + 31], '\0');  // flags
    const std::uint64_t size = type == 1 || type == 5 ? 1 : type == 4 || type == 10 || type == 8 ? 8 : 4;
    data_end += n * m * size;
    last_frame = frame;
    last_id = id;
  }
  EXPECT_EQ(last_frame, static_cast<std::uint64_t>(kFrames - 1));
  EXPECT_EQ(data_end, namelist_location);
  EXPECT_EQ(read_at<std::int64_t>(bytes, bytes.size() - 16), 0) << "the last entry is empty: it ends the index";
}

// A 2D run stored in 3D (output.h5md_pad_3d) reads back in 2D, frames and particles
// as written, also after a resume.
TEST(H5md, A2DRunStoredIn3DReadsBackIn2D) {
  for (const Boundary boundary : {Boundary::periodic, Boundary::walls}) {
    const State<2> s = make_initial_state<2>(small_config(2, 40, 0.1, boundary, 9));
    const std::vector<Frame<2>> frames = flight_frames(s);
    const TempDir dir;
    const std::string path = (dir / "t.h5md").string();
    std::uint64_t mark = 0;
    {
      H5mdWriter<2> writer(path, particles_of(s), "", SnapshotPrecision::double_, true);
      for (int k = 0; k < 3; ++k) writer.write(frames[k]);
      mark = writer.flush();
    }
    {
      H5mdWriter<2> writer(path, particles_of(s), mark, SnapshotPrecision::double_, true);
      for (int k = 3; k < kFrames; ++k) writer.write(frames[k]);
      writer.finish();
    }
    const H5mdReader<2> reader(path);
    ASSERT_EQ(reader.frames(), kFrames);
    EXPECT_EQ(reader.particles().box.length, s.box.length);
    EXPECT_EQ(reader.particles().box.periodic(), boundary == Boundary::periodic);
    EXPECT_EQ(reader.particles().radius, particles_of(s).radius);
    for (int k = 0; k < kFrames; ++k) {
      const Frame<2> f = reader.frame(k);
      EXPECT_EQ(f.time, frames[k].time);
      EXPECT_EQ(f.step, frames[k].step);
      EXPECT_EQ(f.position, frames[k].position) << "frame " << k;
      EXPECT_EQ(f.velocity, frames[k].velocity) << "frame " << k;
      EXPECT_EQ(f.image, frames[k].image) << "frame " << k;
      EXPECT_EQ(f.cluster, frames[k].cluster) << "frame " << k;
    }
    // Read as a 3D run's trajectory it is refused: it says it holds a 2D run.
    EXPECT_THROW(H5mdReader<3>{path}, InputError);
  }
}

TEST(TrajectoryConfig, GsdAndThePaddedH5mdAreConfigurationValues) {
  const Config c = parse_config_text("[output]\nsnapshot_formats = [\"gsd\", \"h5md\"]\nh5md_pad_3d = true\n", "t.toml");
  ASSERT_EQ(c.output.snapshot_formats.size(), 2u);
  EXPECT_EQ(c.output.snapshot_formats[0], SnapshotFormat::gsd);
  EXPECT_TRUE(c.output.h5md_pad_3d);
  const Config again = parse_config_text(to_toml_text(c), "config.toml");
  EXPECT_EQ(again.output.snapshot_formats, c.output.snapshot_formats);
  EXPECT_TRUE(again.output.h5md_pad_3d);
  // Unset, the key is not written: the configuration files of other runs keep their bytes.
  EXPECT_EQ(to_toml_text(parse_config_text("", "t.toml")).find("h5md_pad_3d"), std::string::npos);
  EXPECT_THROW(parse_config_text("[output]\nh5md_pad_3d = 1\n", "t.toml"), InputError);
}

}  // namespace
}  // namespace ballagg
