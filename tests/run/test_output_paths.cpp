// Where ballagg writes and what it reads, as a user meets it through the binary: a run
// directory holds one run (another run's directory is refused, or replaced with
// --overwrite) and has one writer at a time (a lock); an output path that is not a
// regular file (a FIFO, a device, a link) is never replaced; an input file that is not a
// regular file, or is larger than its limit, is refused before it is read; an empty path
// or a --set holding a newline is refused rather than taken for something else. Every
// refusal: one line "ballagg: error: ...", status 2, nothing written.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "ballagg/config/text_file.hpp"
#include "ballagg/io/directory_lock.hpp"
#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {

using testing::Outcome;
using testing::slurp;
using testing::TempDir;

class OutputPaths : public ::testing::Test {
 protected:
  Outcome ballagg(const std::vector<std::string>& args) const { return testing::run_ballagg(args, tmp_.path()); }

  // A run of 16 discs (a few milliseconds) into `out`, with extra arguments.
  Outcome tiny_run(const fs::path& out, std::vector<std::string> extra = {}) const {
    std::vector<std::string> args{"run", "--quiet", "--out", out.string(), "--set", "system.n=16"};
    args.insert(args.end(), extra.begin(), extra.end());
    return ballagg(args);
  }
  fs::path finished_run(const std::string& name) const {
    const fs::path out = tmp_ / name;
    const Outcome o = tiny_run(out);
    EXPECT_EQ(o.status, 0) << o.err;
    return out;
  }

  // The bad-input contract: status 2, one line on stderr holding every needle, nothing on
  // stdout.
  static void expect_refused(const Outcome& o, const std::vector<std::string>& needles) {
    EXPECT_EQ(o.status, 2) << "stderr: " << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << "stderr: " << o.err;
    EXPECT_EQ(o.err.rfind("ballagg: error: ", 0), 0u) << "stderr: " << o.err;
    for (const std::string& n : needles) EXPECT_CONTAINS(o.err, n);
    EXPECT_EQ(o.out, "");
  }

  static std::vector<std::string> names_in(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  TempDir tmp_{"ballagg-test-paths-"};
};

bool is_fifo_node(const fs::path& p) { return fs::is_fifo(fs::symlink_status(p)); }

void make_fifo(const fs::path& p) { ASSERT_EQ(::mkfifo(p.c_str(), 0644), 0) << p; }

// ---------------------------------------------------------------------------------------
// Run directories

TEST_F(OutputPaths, RunIntoADirectoryHoldingAnotherRunIsRefused) {
  const fs::path out = finished_run("run");
  const std::string summary = slurp(out / "summary.json");
  const std::vector<std::string> before = names_in(out);
  expect_refused(tiny_run(out, {"--seed", "9"}), {"--out " + out.string(), "holds another run", "--overwrite"});
  EXPECT_EQ(slurp(out / "summary.json"), summary);
  EXPECT_EQ(names_in(out), before);
}

TEST_F(OutputPaths, OverwriteRemovesTheOldRunsFilesAndNoOther) {
  const fs::path out = tmp_ / "run";
  ASSERT_EQ(tiny_run(out, {"--set", "output.snapshot_every=0.5", "--set", "output.snapshot_formats=[\"xyz\", \"h5md\"]"})
                .status, 0);
  ASSERT_EQ(ballagg({"analyze", out.string()}).status, 0);
  ASSERT_TRUE(fs::exists(out / "trajectory.xyz") && fs::exists(out / "analysis.json"));
  tmp_.write("run/notes.txt", "the user's own file\n");
  tmp_.write("run/frame-3.png", "a picture of the old run\n");
  tmp_.write("run/.trajectory.xyz.tmp", "a temporary file of the old run\n");
  const Outcome o = tiny_run(out, {"--overwrite", "--seed", "9"});
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(names_in(out), (std::vector<std::string>{"config.toml", "final.csv", "final.xyz", "notes.txt", "summary.json",
                                                     "timeseries.csv"}));
  EXPECT_EQ(slurp(out / "notes.txt"), "the user's own file\n");
  EXPECT_CONTAINS(slurp(out / "summary.json"), "\"seed\": 9");
  // --overwrite with --resume makes no sense: refused by the parser.
  expect_refused(ballagg({"run", "--resume", out.string(), "--overwrite"}), {"--overwrite"});
}

TEST_F(OutputPaths, RunIntoASweepDirectoryIsRefusedEvenWithOverwrite) {
  const fs::path out = tmp_ / "sweep";
  fs::create_directories(out);
  tmp_.write("sweep/sweep.toml", "[sweep]\n");
  expect_refused(tiny_run(out, {"--overwrite"}), {"holds a sweep"});
  EXPECT_EQ(names_in(out), std::vector<std::string>{"sweep.toml"});
}

TEST_F(OutputPaths, OverwriteRefusesARunFileThatIsNotARegularFile) {
  const fs::path out = finished_run("run");
  fs::remove(out / "final.xyz");
  make_fifo(out / "final.xyz");
  expect_refused(tiny_run(out, {"--overwrite"}), {(out / "final.xyz").string(), "not a regular file"});
  EXPECT_TRUE(is_fifo_node(out / "final.xyz"));
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

// A process started from the test, killed with SIGKILL at once or waited for.
class Child {
 public:
  explicit Child(std::vector<std::string> args) {
    pid_ = ::fork();
    if (pid_ == 0) {
      std::vector<char*> argv;
      for (std::string& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, STDOUT_FILENO);
      ::dup2(null, STDERR_FILENO);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
  }
  ~Child() {
    if (pid_ > 0) kill();
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  void kill() {
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

// Waits (up to a minute, for sanitizer builds) for `p` to exist.
bool appears(const fs::path& p) {
  for (int k = 0; k < 6000 && !fs::exists(p); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return fs::exists(p);
}

TEST_F(OutputPaths, ANewRunCannotTakeOverTheCheckpointOfAnotherRun) {
  // An interrupted run (killed after a checkpoint), then another run into its directory:
  // the second is refused, so that --resume continues the first run's trajectory with the
  // first run's frames only (else a resume spliced two runs' frames together).
  const fs::path out = tmp_ / "run";
  Child first({BALLAGG_BINARY, "run", "--quiet", "--out", out.string(), "--set", "system.n=2000", "--set",
               "collision.outcome=\"bounce\"", "--set", "stop.wall_seconds=1.5", "--set", "output.checkpoint_every=0.1",
               "--set", "output.snapshot_every=1", "--set", "output.snapshot_formats=[\"xyz\"]"});
  ASSERT_TRUE(appears(out / "checkpoint.bin"));
  first.kill();
  const std::string checkpoint = slurp(out / "checkpoint.bin");
  const std::string trajectory = slurp(out / ".trajectory.xyz.tmp");
  expect_refused(tiny_run(out, {"--seed", "9", "--set", "output.snapshot_every=0.1", "--set",
                                "output.snapshot_formats=[\"xyz\"]"}),
                 {"holds another run", "checkpoint.bin"});
  EXPECT_EQ(slurp(out / "checkpoint.bin"), checkpoint);
  EXPECT_EQ(slurp(out / ".trajectory.xyz.tmp"), trajectory);
  const Outcome resumed = ballagg({"run", "--quiet", "--resume", out.string()});
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  const Outcome verified = ballagg({"verify", out.string()});
  EXPECT_EQ(verified.status, 0) << verified.out << verified.err;
  EXPECT_FALSE(fs::exists(out / kLockFile));
}

TEST_F(OutputPaths, ASecondWriterOfALockedDirectoryIsRefused) {
  // The test holds the lock, as a running `ballagg run` would.
  const fs::path run = finished_run("run");
  const fs::path empty = tmp_ / "empty";
  fs::create_directories(empty);
  const fs::path sweep_file = tmp_.write("tiny.toml", "[sweep]\nrealizations = 1\n[grid]\nsystem.n = [16]\n");
  {
    const DirectoryLock run_lock(run.string());
    const DirectoryLock empty_lock(empty.string());
    const std::string holder = fmt::format("(pid {})", ::getpid());
    expect_refused(ballagg({"run", "--quiet", "--resume", run.string()}), {run.string(), "another ballagg process", holder});
    expect_refused(tiny_run(empty), {empty.string(), "another ballagg process", holder});
    expect_refused(ballagg({"analyze", run.string()}), {run.string(), "another ballagg process"});
    expect_refused(ballagg({"analyze", run.string(), "--out", empty.string()}), {empty.string(), "another ballagg process"});
    expect_refused(ballagg({"sweep", sweep_file.string(), "--quiet", "--out", empty.string()}),
                   {empty.string(), "another ballagg process"});
    EXPECT_EQ(names_in(empty), std::vector<std::string>{kLockFile});
  }
  // Released: the same commands go through, and leave no lock file.
  ASSERT_EQ(tiny_run(empty).status, 0);
  EXPECT_FALSE(fs::exists(empty / kLockFile));
  EXPECT_FALSE(fs::exists(run / kLockFile));
  EXPECT_EQ(ballagg({"analyze", run.string()}).status, 0);
  EXPECT_FALSE(fs::exists(run / kLockFile));
}

TEST_F(OutputPaths, ALockLeftByAKilledRunDoesNotBlockTheNext) {
  // kill -9 leaves the lock file but not the lock (the kernel releases it).
  const fs::path out = tmp_ / "killed";
  fs::create_directories(out);
  tmp_.write("killed/.ballagg.lock", "4194304\n");
  ASSERT_EQ(tiny_run(out).status, 0);
  EXPECT_FALSE(fs::exists(out / kLockFile));
}

// ---------------------------------------------------------------------------------------
// Arguments

TEST_F(OutputPaths, EmptyPathArgumentsAreRefused) {
  const fs::path run = finished_run("run");
  expect_refused(ballagg({"run", "--resume", ""}), {"--resume", "empty argument"});
  expect_refused(ballagg({"run", "--quiet", "--out", ""}), {"--out", "empty argument"});
  expect_refused(ballagg({"run", "", "--out", (tmp_ / "o").string()}), {"config", "empty argument"});
  expect_refused(ballagg({"render", run.string(), "--png", ""}), {"--png", "empty argument"});
  expect_refused(ballagg({"analyze", run.string(), "--out", ""}), {"--out", "empty argument"});
  const fs::path sweep_file = tmp_.write("tiny.toml", "[sweep]\nrealizations = 1\n[grid]\nsystem.n = [16]\n");
  expect_refused(ballagg({"sweep", sweep_file.string(), "--out", ""}), {"--out", "empty argument"});
  EXPECT_FALSE(fs::exists(tmp_ / "o"));
  EXPECT_FALSE(fs::exists(run / "final.png"));
}

TEST_F(OutputPaths, ControlCharactersInSetAreRefusedNamingTheArgument) {
  const fs::path out = tmp_ / "o";
  expect_refused(tiny_run(out, {"--set", "stop.time=0.5\nsystem.n=7"}),
                 {"--set \"stop.time=0.5\\nsystem.n=7\"", "control character \\n"});
  expect_refused(tiny_run(out, {"--set", std::string("system.n=7\x01")}), {"control character \\x01"});
  expect_refused(ballagg({"config", "--set", "stop.time=0.5\r"}), {"control character \\r"});
  EXPECT_FALSE(fs::exists(out));
}

// ---------------------------------------------------------------------------------------
// Input files

TEST_F(OutputPaths, PlotOfASweepTableThatIsNotUtf8IsOneLine) {
  const fs::path sweep = tmp_ / "sweep";
  fs::create_directories(sweep);
  tmp_.write("sweep/sweep.csv", "method,runs\ned,\xff\xfe" "2\n");
  const Outcome o = ballagg({"plot", sweep.string()});
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
  EXPECT_EQ(o.err.rfind("ballagg plot: error: " + (sweep / "sweep.csv").string() + ": not UTF-8 text", 0), 0u) << o.err;
  EXPECT_EQ(names_in(sweep), std::vector<std::string>{"sweep.csv"});
}


TEST_F(OutputPaths, InputFilesThatAreNotRegularFilesAreRefusedBeforeReading) {
  const fs::path dir = tmp_ / "a-directory.toml", fifo = tmp_ / "fifo.toml", zero = tmp_ / "zero.toml";
  fs::create_directories(dir);
  make_fifo(fifo);
  fs::create_symlink("/dev/zero", zero);
  const fs::path out = tmp_ / "o";
  expect_refused(ballagg({"run", "--quiet", dir.string(), "--out", out.string()}), {dir.string(), "is a directory"});
  expect_refused(ballagg({"run", "--quiet", fifo.string(), "--out", out.string()}), {fifo.string(), "FIFO"});
  expect_refused(ballagg({"run", "--quiet", zero.string(), "--out", out.string()}), {zero.string(), "character device"});
  expect_refused(ballagg({"config", zero.string()}), {"character device"});
  // State files (initial.file) and sweep files.
  for (const fs::path& state : {dir, fifo, zero})
    expect_refused(tiny_run(out, {"--set", "initial.positions=\"file\"", "--set", "system.box_length=20", "--set",
                                  "initial.file=" + state.string()}),
                   {state.string(), "cannot read the state file"});
  expect_refused(ballagg({"sweep", fifo.string(), "--out", out.string()}), {fifo.string(), "cannot read the sweep file"});
  expect_refused(ballagg({"sweep", zero.string(), "--out", out.string()}), {zero.string(), "character device"});
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(OutputPaths, AConfigurationLargerThanItsLimitIsRefused) {
  const fs::path big = tmp_.write("big.toml", "");
  fs::resize_file(big, kMaxSettingsFileBytes + 1);  // sparse: costs no disk
  expect_refused(ballagg({"run", "--quiet", big.string(), "--out", (tmp_ / "o").string()}),
                 {big.string(), fmt::format("more than the limit of {} bytes", kMaxSettingsFileBytes)});
  EXPECT_FALSE(fs::exists(tmp_ / "o"));
}

TEST_F(OutputPaths, ACheckpointThatIsNotARegularFileIsRefused) {
  const fs::path run = tmp_ / "run";
  fs::create_directories(run / "checkpoint.bin");
  expect_refused(ballagg({"run", "--quiet", "--resume", run.string()}), {"checkpoint.bin", "is a directory"});
  fs::remove(run / "checkpoint.bin");
  fs::create_symlink("/dev/zero", run / "checkpoint.bin");
  expect_refused(ballagg({"run", "--quiet", "--resume", run.string()}), {"checkpoint.bin", "character device"});
  fs::remove(run / "checkpoint.bin");
  make_fifo(run / "checkpoint.bin");
  expect_refused(ballagg({"run", "--quiet", "--resume", run.string()}), {"checkpoint.bin", "FIFO"});
  EXPECT_EQ(names_in(run), std::vector<std::string>{"checkpoint.bin"});
}

TEST(ReadTextFile, RefusesWhatIsNotARegularFileOrIsLargerThanTheLimit) {
  const TempDir dir;
  const fs::path fifo = dir / "fifo", zero = dir / "zero", sub = dir / "sub";
  make_fifo(fifo);  // no writer: opening it must not wait for one
  fs::create_symlink("/dev/zero", zero);
  fs::create_directories(sub);
  auto error_of = [](const fs::path& p, std::uint64_t limit) {
    try {
      read_text_file(p.string(), "state file", limit);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of(fifo, 100), fifo.string() + ": cannot read the state file: it is a FIFO, not a regular file");
  EXPECT_EQ(error_of(zero, 100), zero.string() + ": cannot read the state file: it is a character device, not a regular file");
  EXPECT_EQ(error_of(sub, 100), sub.string() + ": cannot read the state file: it is a directory");
  const fs::path five = dir.write("five", "12345");
  EXPECT_EQ(error_of(five, 4), five.string() + ": cannot read the state file: 5 bytes, more than the limit of 4 bytes");
  EXPECT_EQ(read_text_file(five.string(), "state file", 5), "12345");
  EXPECT_EQ(read_text_file(dir.write("empty", "").string(), "state file", 5), "");
}

// ---------------------------------------------------------------------------------------
// Output files that are not regular files

TEST_F(OutputPaths, RenderNeverReplacesAFifoOrALink) {
  const fs::path run = finished_run("run");
  const fs::path fifo = tmp_ / "fifo.png", link = tmp_ / "link.png";
  const fs::path target = tmp_.write("target.png", "the link's target\n");
  make_fifo(fifo);
  fs::create_symlink(target, link);
  expect_refused(ballagg({"render", run.string(), "--png", fifo.string()}), {fifo.string(), "FIFO"});
  EXPECT_TRUE(is_fifo_node(fifo));
  expect_refused(ballagg({"render", run.string(), "--png", link.string()}), {link.string(), "symbolic link"});
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(slurp(target), "the link's target\n");
  EXPECT_EQ(names_in(tmp_.path()), (std::vector<std::string>{"fifo.png", "link.png", "run", "target.png"}));
}

TEST_F(OutputPaths, RenderNeverReplacesACharacterDevice) {
  if (::geteuid() != 0) GTEST_SKIP() << "creating a device node (mknod) needs root";
  const fs::path run = finished_run("run");
  const fs::path device = tmp_ / "device.png";
  ASSERT_EQ(::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)), 0);  // a copy of /dev/null
  expect_refused(ballagg({"render", run.string(), "--png", device.string()}), {device.string(), "character device"});
  EXPECT_TRUE(fs::is_character_file(fs::symlink_status(device)));
}

}  // namespace
}  // namespace ballagg
