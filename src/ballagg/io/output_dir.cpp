#include "ballagg/io/output_dir.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"
#include "ballagg/core/run_guard.hpp"
#include "ballagg/io/atomic_file.hpp"
#include "ballagg/io/output_error.hpp"

namespace fs = std::filesystem;

namespace ballagg {

std::string default_output_dir(const std::string& parent) {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm local{};
  localtime_r(&now, &local);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &local);
  std::string dir = (fs::path(parent) / stamp).string();
  for (int k = 2; fs::exists(dir); ++k) dir = (fs::path(parent) / fmt::format("{}-{}", stamp, k)).string();
  return dir;
}

bool prepare_output_dir(const std::string& dir) {
  std::error_code ec;
  const bool existed = fs::exists(dir, ec);
  if (existed && !fs::is_directory(dir, ec))
    throw InputError(fmt::format("--out {}: exists and is not a directory", dir));
  if (!existed && !fs::create_directories(dir, ec))
    throw InputError(fmt::format("--out {}: cannot create the output directory: {}", dir, ec.message()));
  const fs::path probe = fs::path(dir) / ".ballagg-write-test";
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (f == nullptr) {
    const std::string reason = std::strerror(errno);
    if (!existed) fs::remove(dir, ec);
    throw InputError(fmt::format("--out {}: cannot write in the output directory: {}", dir, reason));
  }
  std::fclose(f);
  fs::remove(probe, ec);
  return !existed;
}

std::string temporary_path_for(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / fmt::format(".{}.tmp", p.filename().string())).string();
}

namespace {

// What is at a path that is not a regular file, for messages.
const char* node_kind(mode_t mode) {
  if (S_ISLNK(mode))
    return "it is a symbolic link (output files are replaced by renaming, which would replace the link; give the path "
           "of the file itself)";
  if (S_ISDIR(mode)) return "it is a directory";
  if (S_ISCHR(mode)) return "it is a character device (only a regular file is replaced)";
  if (S_ISBLK(mode)) return "it is a block device (only a regular file is replaced)";
  if (S_ISFIFO(mode)) return "it is a FIFO (only a regular file is replaced)";
  if (S_ISSOCK(mode)) return "it is a socket (only a regular file is replaced)";
  return "it is not a regular file (only a regular file is replaced)";
}

}  // namespace

void check_output_path(const std::string& path) {
  struct stat st{};
  // Nothing there (or a path that cannot be reached: writing will say why).
  if (::lstat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return;
  throw OutputError(fmt::format("{}: cannot write: {}", path, node_kind(st.st_mode)));
}

std::string fresh_temporary_for(const std::string& path) {
  check_output_path(path);
  std::string temporary = temporary_path_for(path);
  struct stat st{};
  if (::lstat(temporary.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && ::unlink(temporary.c_str()) != 0)
    throw OutputError(fmt::format("{}: cannot write: its temporary file {}: {}", path, temporary, node_kind(st.st_mode)));
  return temporary;
}

void rename_into_place(const std::string& temporary, const std::string& path) {
  std::error_code ec;
  try {
    check_output_path(path);
  } catch (const OutputError&) {
    fs::remove(temporary, ec);
    throw;
  }
  fs::rename(temporary, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw_output_error(path, ec.value());
  }
}

void reclaim_completed_file(const std::string& path) {
  const std::string temporary = temporary_path_for(path);
  std::error_code ec;
  if (fs::exists(temporary, ec) || !fs::exists(path, ec)) return;
  fs::rename(path, temporary, ec);
}

std::uint64_t checked_temporary_size(const std::string& path, std::uint64_t bytes) {
  check_output_path(path);
  reclaim_completed_file(path);
  const std::string temporary = temporary_path_for(path);
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(temporary, ec);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw InputError(fmt::format("{}: the trajectory of the checkpointed run is not a regular file (cannot resume it)",
                                 temporary));
  const std::uintmax_t size = fs::file_size(temporary, ec);
  if (ec || size < bytes)
    throw InputError(fmt::format("{}: the trajectory of the checkpointed run is {} (cannot resume it)", temporary,
                                 ec ? "missing" : "shorter than at the checkpoint"));
  return bytes;
}

void write_file_atomically(const std::string& dir, const std::string& name, const std::string& content) {
  const CriticalWrite not_to_be_cut;  // a forced quit waits for the rename
  AtomicFile file((fs::path(dir) / name).string());
  file.write(content);
  file.commit();
}

namespace {

class FileSink final : public ByteSink {
 public:
  explicit FileSink(AtomicFile& file) : file_(file) {}
  void write(std::string_view bytes) override { file_.write(bytes); }

 private:
  AtomicFile& file_;
};

}  // namespace

void write_file_atomically(const std::string& dir, const std::string& name,
                           const std::function<void(ByteSink&)>& produce) {
  const CriticalWrite not_to_be_cut;  // a forced quit waits for the rename
  AtomicFile file((fs::path(dir) / name).string());
  FileSink sink(file);
  produce(sink);
  file.commit();
}

}  // namespace ballagg
