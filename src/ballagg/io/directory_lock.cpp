#include "ballagg/io/directory_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {
namespace {

// The pid the holder wrote in the lock file, for the message ("" if none can be read).
std::string holder_of(int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
  if (n <= 0) return "";
  std::string pid(text, static_cast<std::size_t>(n));
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid.find_first_not_of("0123456789") == std::string::npos && !pid.empty() ? fmt::format(" (pid {})", pid) : "";
}

bool same_file(int fd, const std::string& path) {
  struct stat opened{}, named{};
  return ::fstat(fd, &opened) == 0 && ::lstat(path.c_str(), &named) == 0 && opened.st_dev == named.st_dev &&
         opened.st_ino == named.st_ino;
}

}  // namespace

DirectoryLock::DirectoryLock(const std::string& dir) : path_((std::filesystem::path(dir) / kLockFile).string()) {
  // The holder removes the lock file when it is done. A process that opened the file just
  // before that holds a lock on a file no longer in the directory: it checks that the
  // file it locked is still the one named, and else starts again with the new one.
  for (;;) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
    if (fd_ < 0)
      throw InputError(fmt::format("{}: cannot lock the directory for writing: {}", dir, std::strerror(errno)));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      const std::string holder = error == EWOULDBLOCK ? holder_of(fd_) : "";
      ::close(fd_);
      fd_ = -1;
      if (error == EWOULDBLOCK)
        throw InputError(fmt::format("{}: another ballagg process{} is writing this directory (wait until it ends, "
                                     "or choose another directory)", dir, holder));
      throw InputError(fmt::format("{}: cannot lock the directory for writing: {}", dir, std::strerror(error)));
    }
    if (same_file(fd_, path_)) break;
    ::close(fd_);
  }
  const std::string pid = fmt::format("{}\n", ::getpid());
  // The pid is only for the message of a refused writer: a failure to write it is no error.
  if (::ftruncate(fd_, 0) == 0) {
    [[maybe_unused]] const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
  }
}

DirectoryLock::DirectoryLock(DirectoryLock&& other) noexcept
    : path_(std::move(other.path_)), fd_(std::exchange(other.fd_, -1)) {}

DirectoryLock::~DirectoryLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while locked: see the constructor
  ::close(fd_);
}

}  // namespace ballagg
