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
#include <string>

#include <gtest/gtest.h>

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

TEST(AtomicFile, CheckpointBeyondAFileSizeLimitKeepsThePreviousOne) {
  // The checkpoint is replaced only by a complete one: a failed write leaves the previous
  // checkpoint, from which the run can still be resumed.
  const TempDir dir;
  Checkpoint small;
  small.engine = "ed";
  small.state = "previous";
  write_checkpoint_file(dir.path().string(), small);
  Checkpoint large = small;
  large.state = std::string(100000, 's');
  const std::string message = output_error_of([&] {
    const FileSizeLimit limit(16384);
    write_checkpoint_file(dir.path().string(), large);
  });
  EXPECT_EQ(message, (dir / kCheckpointFile).string() + ": cannot write: " + std::strerror(EFBIG));
  EXPECT_EQ(read_checkpoint_file(dir.path().string()).state, "previous");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
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
