// Output files are written under a temporary name and renamed when complete: a reader
// never sees one half-written, and a failure to write (a full disk, a file-size limit, a
// directory that cannot be written) is one OutputError naming the file and the reason,
// with the temporary file gone.
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/io/atomic_file.hpp"
#include "ballagg/io/checkpoint_file.hpp"
#include "ballagg/io/output_dir.hpp"
#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {
using testing::slurp;
using testing::TempDir;

// The message of the OutputError thrown by `f`, or "" when none is.
template <class F>
std::string output_error_of(F&& f) {
  try {
    f();
  } catch (const OutputError& e) {
    return e.what();
  }
  return "";
}

// A file-size limit for the test's process, with SIGXFSZ ignored: a write beyond it fails
// with EFBIG, as a write on a full disk fails with ENOSPC. Lifted when it goes.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    previous_ = std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limited{bytes, saved_.rlim_max};
    setrlimit(RLIMIT_FSIZE, &limited);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  void (*previous_)(int) = SIG_DFL;
};

TEST(AtomicFile, AppearsOnlyWhenCommitted) {
  const TempDir dir;
  const std::string path = (dir / "final.csv").string();
  {
    AtomicFile f(path);
    f.write("x,y\n");
    f.write("1,2\n");
    EXPECT_FALSE(fs::exists(path)) << "visible before it is complete";
    EXPECT_TRUE(fs::exists(f.temporary()));
    f.commit();
  }
  EXPECT_EQ(slurp(path), "x,y\n1,2\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(AtomicFile, AbandonedLeavesNothing) {
  const TempDir dir;
  { AtomicFile(dir / "final.csv").write("x,y\n"); }
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(AtomicFile, WriteBeyondAFileSizeLimitNamesTheFileAndLeavesNothing) {
  const TempDir dir;
  const std::string path = (dir / "final.csv").string();
  const std::string message = output_error_of([&] {
    const FileSizeLimit limit(4096);
    AtomicFile f(path);
    f.write(std::string(10000, 'x'));
  });
  EXPECT_EQ(message, path + ": cannot write: " + std::strerror(EFBIG));
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(AtomicFile, DirectoryThatIsGoneNamesTheFile) {
  const TempDir dir;
  const std::string path = (dir / "gone" / "summary.json").string();
  EXPECT_EQ(output_error_of([&] { write_file_atomically((dir / "gone").string(), "summary.json", "{}\n"); }),
            path + ": cannot write: " + std::strerror(ENOENT));
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(AtomicFile, RenameOverADirectoryNamesTheFileAndLeavesNoTemporary) {
  // A directory where the file should go: everything is written, the rename fails.
  const TempDir dir;
  fs::create_directory(dir / "final.csv");
  fs::create_directory(dir / "final.csv" / "inside");  // a non-empty directory is never replaced
  const std::string message = output_error_of([&] { write_file_atomically(dir.path().string(), "final.csv", "x\n"); });
  EXPECT_EQ(message.rfind((dir / "final.csv").string() + ": cannot write: ", 0), 0u) << message;
  EXPECT_FALSE(fs::exists(temporary_path_for((dir / "final.csv").string())));
}

TEST(AtomicFile, KeptTemporaryOutlivesAFailureAndIsCutBackOnResume) {
  // A trajectory a checkpoint refers to: a failed write leaves the temporary file (the
  // run can be resumed), and the resumed writer continues it from the checkpoint's mark.
  const TempDir dir;
  const std::string path = (dir / "trajectory.xyz").string();
  {
    AtomicFile f(path);
    f.write("frame 1\n");
    f.keep();
    const std::string message = output_error_of([&] {
      const FileSizeLimit limit(4096);
      f.write(std::string(10000, 'x'));
    });
    EXPECT_EQ(message, path + ": cannot write: " + std::strerror(EFBIG));
  }
  ASSERT_TRUE(fs::exists(temporary_path_for(path)));
  {
    AtomicFile resumed(path, 8);
    resumed.write("frame 2\n");
    resumed.commit();
  }
  EXPECT_EQ(slurp(path), "frame 1\nframe 2\n");
  EXPECT_FALSE(fs::exists(temporary_path_for(path)));
}

// Writes a checkpoint whose state is "previous" into dir: the one a failed write must leave.
Checkpoint write_previous_checkpoint(const TempDir& dir) {
  Checkpoint previous;
  previous.engine = "ed";
  previous.state = "previous";
  write_checkpoint_file(dir.path().string(), previous);
  return previous;
}

// The previous checkpoint is still there, and nothing else (no temporary file).
void expect_only_the_previous_checkpoint(const TempDir& dir) {
  EXPECT_EQ(read_checkpoint_file(dir.path().string()).state, "previous");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(AtomicFile, CheckpointBeyondAFileSizeLimitKeepsThePreviousOne) {
  // The checkpoint is replaced only by a complete one: a failed write leaves the previous
  // checkpoint, from which the run can still be resumed.
  const TempDir dir;
  Checkpoint large = write_previous_checkpoint(dir);
  large.state = std::string(100000, 's');
  const std::string message = output_error_of([&] {
    const FileSizeLimit limit(16384);
    write_checkpoint_file(dir.path().string(), large);
  });
  EXPECT_EQ(message, (dir / kCheckpointFile).string() + ": cannot write: " + std::strerror(EFBIG));
  expect_only_the_previous_checkpoint(dir);
}

// ---- Streamed checkpoints and output files ----

// The checkpoint format assembled by hand (checkpoint_file.hpp): magic, format version,
// byte order, payload size, the payload (fields, then the sections each after its
// length), CRC-32 of the payload.
std::string checkpoint_bytes_by_hand(const Checkpoint& c) {
  ByteWriter payload;
  payload.put_string(c.program_version);
  payload.put<std::int32_t>(c.dimension);
  payload.put_string(c.engine);
  payload.put_string(c.config_toml);
  payload.put(c.wall_seconds);
  for (const std::string* s : {&c.totals, &c.state, &c.engine_state, &c.timeseries, &c.snapshots}) payload.put_string(*s);
  ByteWriter header;
  header.put(kCheckpointFormat);
  header.put(std::uint32_t{0x01020304});
  header.put<std::uint64_t>(payload.bytes().size());
  const auto crc = static_cast<std::uint32_t>(crc32_z(0L, reinterpret_cast<const Bytef*>(payload.bytes().data()),
                                                      static_cast<z_size_t>(payload.bytes().size())));
  std::string bytes = std::string("BALLAGG CHECKPT\n") + header.bytes() + payload.bytes();
  bytes.append(reinterpret_cast<const char*>(&crc), sizeof crc);
  return bytes;
}

// Sections of a few MB put in many small values and one long array: the writer's buffer
// is handed on several times, once past its length in one piece.
void put_state_section(ByteWriter& w) {
  for (std::int64_t k = 0; k < 200'000; ++k) w.put(static_cast<double>(k) / 3.0);
}
void put_engine_section(ByteWriter& w) {
  w.put(std::int32_t{42});
  w.put_vector(std::vector<std::int64_t>(kByteWriterBufferBytes / 8 + 5, 7));
  for (std::int32_t k = 0; k < 100'000; ++k) w.put(k);
}

Checkpoint checkpoint_around_streamed_sections() {
  Checkpoint c;
  c.program_version = "test";
  c.engine = "ed";
  c.config_toml = "[system]\nn = 10\n";
  c.wall_seconds = 2.25;
  c.totals = "totals";
  c.timeseries = std::string(1000, 't');
  c.snapshots = "snapshots";
  return c;
}

TEST(AtomicFile, StreamedCheckpointHasTheBytesOfTheFormat) {
  const TempDir dir;
  const Checkpoint head = checkpoint_around_streamed_sections();
  write_checkpoint_file(dir.path().string(), head, put_state_section, put_engine_section);
  Checkpoint whole = head;
  ByteWriter state, engine;
  put_state_section(state);
  put_engine_section(engine);
  whole.state = state.bytes();
  whole.engine_state = engine.bytes();
  const std::string expected = checkpoint_bytes_by_hand(whole);
  EXPECT_EQ(encode_checkpoint(whole), expected);
  EXPECT_EQ(slurp((dir / kCheckpointFile).string()), expected);
  const Checkpoint back = read_checkpoint_file(dir.path().string());
  EXPECT_EQ(back.engine_state, whole.engine_state);
  EXPECT_EQ(back.timeseries, whole.timeseries);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(AtomicFile, StreamedCheckpointThatFailsKeepsThePreviousOne) {
  // A write beyond a file-size limit, and a section whose owner throws while putting it:
  // each leaves the previous checkpoint and no temporary file.
  const TempDir dir;
  write_previous_checkpoint(dir);
  const Checkpoint head = checkpoint_around_streamed_sections();
  const std::string message = output_error_of([&] {
    const FileSizeLimit limit(1 << 20);
    write_checkpoint_file(dir.path().string(), head, put_state_section, put_engine_section);
  });
  EXPECT_EQ(message, (dir / kCheckpointFile).string() + ": cannot write: " + std::strerror(EFBIG));
  auto throwing = [](ByteWriter& w) {
    put_engine_section(w);
    throw std::runtime_error("engine failed");
  };
  EXPECT_THROW(write_checkpoint_file(dir.path().string(), head, put_state_section, throwing), std::runtime_error);
  expect_only_the_previous_checkpoint(dir);
}

TEST(AtomicFile, StreamedOutputFileHoldsWhatWasHandedOn) {
  const TempDir dir;
  const std::string line = "0.1,0.2,0.3\n";
  write_file_atomically(dir.path().string(), "final.csv", [&](ByteSink& out) {
    for (int k = 0; k < 3; ++k) out.write(line);
  });
  EXPECT_EQ(slurp((dir / "final.csv").string()), line + line + line);
}

TEST(AtomicFile, StreamedOutputFileThatFailsLeavesNothing) {
  const TempDir dir;
  const std::string message = output_error_of([&] {
    const FileSizeLimit limit(4096);
    write_file_atomically(dir.path().string(), "final.csv", [](ByteSink& out) {
      for (int k = 0; k < 100; ++k) out.write(std::string(1000, 'x'));
    });
  });
  EXPECT_EQ(message, (dir / "final.csv").string() + ": cannot write: " + std::strerror(EFBIG));
  EXPECT_THROW(write_file_atomically(dir.path().string(), "final.csv",
                                     [](ByteSink& out) {
                                       out.write("half");
                                       throw std::runtime_error("cut");
                                     }),
               std::runtime_error);
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

// ---- Output paths that are not regular files (docs/outputs.md, "Output files") ----

bool is_fifo_node(const fs::path& p) { return fs::is_fifo(fs::symlink_status(p)); }

TEST(AtomicFile, NeverReplacesAFifo) {
  const TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "final.csv").c_str(), 0644), 0);
  const std::string message = output_error_of([&] { write_file_atomically(dir.path().string(), "final.csv", "x\n"); });
  EXPECT_EQ(message, (dir / "final.csv").string() + ": cannot write: it is a FIFO (only a regular file is replaced)");
  EXPECT_TRUE(is_fifo_node(dir / "final.csv"));
  EXPECT_FALSE(fs::exists(temporary_path_for((dir / "final.csv").string())));
}

TEST(AtomicFile, NeverReplacesALinkNorWritesThroughIt) {
  // The rule for links: refused, whatever they point to. The link and its target stay.
  const TempDir dir;
  const fs::path target = dir.write("target.csv", "the target\n");
  fs::create_symlink(target, dir / "final.csv");
  fs::create_symlink(dir / "nothing", dir / "dangling.csv");
  for (const char* name : {"final.csv", "dangling.csv"}) {
    const std::string message = output_error_of([&] { write_file_atomically(dir.path().string(), name, "x\n"); });
    EXPECT_EQ(message.rfind((dir / name).string() + ": cannot write: it is a symbolic link", 0), 0u) << message;
    EXPECT_TRUE(fs::is_symlink(dir / name));
  }
  EXPECT_EQ(slurp(target), "the target\n");
  EXPECT_FALSE(fs::exists(dir / "nothing"));
}

TEST(AtomicFile, ALinkAtTheTemporaryNameIsNotWrittenThrough) {
  // A link left (or planted) at .NAME.tmp: the file is written anew beside it, never into
  // the link's target.
  const TempDir dir;
  const fs::path victim = dir.write("victim", "untouched\n");
  fs::create_symlink(victim, temporary_path_for((dir / "final.csv").string()));
  write_file_atomically(dir.path().string(), "final.csv", "x\n");
  EXPECT_EQ(slurp(dir / "final.csv"), "x\n");
  EXPECT_FALSE(fs::is_symlink(dir / "final.csv"));
  EXPECT_EQ(slurp(victim), "untouched\n");
}

TEST(AtomicFile, NeverReplacesACharacterDevice) {
  if (::geteuid() != 0) GTEST_SKIP() << "creating a device node (mknod) needs root";
  const TempDir dir;
  const fs::path device = dir / "full";
  ASSERT_EQ(::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 7)), 0);  // a copy of /dev/full
  const std::string message = output_error_of([&] { write_file_atomically(dir.path().string(), "full", "x\n"); });
  EXPECT_EQ(message, device.string() + ": cannot write: it is a character device (only a regular file is replaced)");
  EXPECT_TRUE(fs::is_character_file(fs::symlink_status(device)));
}

TEST(AtomicFile, AFifoPutInPlaceWhileWritingIsNotReplaced) {
  // What is at the path is checked again at the rename.
  const TempDir dir;
  const std::string path = (dir / "summary.json").string();
  const std::string message = output_error_of([&] {
    AtomicFile file(path);
    file.write("{}\n");
    ASSERT_EQ(::mkfifo(path.c_str(), 0644), 0);
    file.commit();
  });
  EXPECT_EQ(message, path + ": cannot write: it is a FIFO (only a regular file is replaced)");
  EXPECT_TRUE(is_fifo_node(path));
  EXPECT_FALSE(fs::exists(temporary_path_for(path)));
}

TEST(RenameIntoPlace, NeverReplacesAFifoOrALink) {
  // The path of the files that libraries write (HDF5, cairo, ffmpeg).
  const TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "a.png").c_str(), 0644), 0);
  fs::create_symlink(dir / "elsewhere.png", dir / "b.png");
  for (const char* name : {"a.png", "b.png"}) {
    const std::string path = (dir / name).string();
    const std::string temporary = fresh_temporary_for(path.substr(0, path.size() - 4) + ".ok");
    testing::write(temporary, "picture\n");
    EXPECT_EQ(output_error_of([&] { fresh_temporary_for(path); }).rfind(path + ": cannot write: it is a ", 0), 0u);
    const std::string message = output_error_of([&] { rename_into_place(temporary, path); });
    EXPECT_EQ(message.rfind(path + ": cannot write: it is a ", 0), 0u) << message;
    EXPECT_FALSE(fs::exists(temporary));
  }
  EXPECT_TRUE(is_fifo_node(dir / "a.png"));
  EXPECT_TRUE(fs::is_symlink(dir / "b.png"));
  EXPECT_FALSE(fs::exists(dir / "elsewhere.png"));
}

}  // namespace
}  // namespace ballagg
