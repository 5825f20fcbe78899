#include "ballagg/io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <utility>

#include "ballagg/io/output_dir.hpp"

namespace ballagg {

namespace {

// The temporary file is opened without following a link and without waiting (a FIFO put
// in its place since fresh_temporary_for looked), and must then be a regular file.
constexpr int kTemporaryFlags = O_WRONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK;

bool regular(int fd) {
  struct stat st{};
  return ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), temporary_(fresh_temporary_for(path_)) {
  registered_.hold(temporary_);
  fd_ = ::open(temporary_.c_str(), kTemporaryFlags | O_CREAT | O_TRUNC, 0644);
  if (fd_ < 0) fail(errno);
  if (!regular(fd_)) fail(EINVAL);
}

AtomicFile::AtomicFile(std::string path, std::uint64_t size)
    : path_(std::move(path)), temporary_(temporary_path_for(path_)), keep_(true) {
  check_output_path(path_);
  // Not O_APPEND: write_at must be able to write before the end (Linux's pwrite appends
  // on a file opened with it). Writes continue at the end, where the seek puts them.
  fd_ = ::open(temporary_.c_str(), kTemporaryFlags);
  if (fd_ < 0) fail(errno);
  if (!regular(fd_)) fail(EINVAL);
  if (::ftruncate(fd_, static_cast<off_t>(size)) != 0) fail(errno);
  if (::lseek(fd_, static_cast<off_t>(size), SEEK_SET) < 0) fail(errno);
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!keep_ && !temporary_.empty()) std::remove(temporary_.c_str());
}

void AtomicFile::write(std::string_view bytes) {
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t w = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0) fail(errno);
    if (w == 0) fail(ENOSPC);  // no progress and no error: a full device
    done += static_cast<std::size_t>(w);
  }
}

void AtomicFile::write_at(std::uint64_t offset, std::string_view bytes) {
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t w = ::pwrite(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(offset + done));
    if (w < 0 && errno == EINTR) continue;
    if (w < 0) fail(errno);
    if (w == 0) fail(ENOSPC);
    done += static_cast<std::size_t>(w);
  }
}

void AtomicFile::sync() {
  if (::fsync(fd_) != 0) fail(errno);
}

void AtomicFile::commit() {
  const int fd = std::exchange(fd_, -1);
  // close() can be the first to report a write that did not reach the disk (NFS, quotas).
  if (::close(fd) != 0) fail(errno);
  // Whatever was put at the path while the file was written is not replaced unless it
  // is a regular file.
  try {
    check_output_path(path_);
  } catch (const OutputError&) {
    if (!keep_) std::remove(temporary_.c_str());
    temporary_.clear();
    throw;
  }
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) fail(errno);
  temporary_.clear();  // it is the file now
  registered_.release();
}

void AtomicFile::fail(int error) {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
  // A temporary file that a checkpoint refers to stays: a resumed run cuts it back to
  // what the checkpoint saw. Any other is removed: nothing half-written is left.
  if (!keep_) std::remove(temporary_.c_str());
  temporary_.clear();
  throw_output_error(path_, error);
}

}  // namespace ballagg
