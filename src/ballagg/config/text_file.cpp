#include "ballagg/config/text_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {
namespace {

// What a file that is not a regular file is, for messages.
const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "it is a directory";
  if (S_ISCHR(mode)) return "it is a character device, not a regular file";
  if (S_ISBLK(mode)) return "it is a block device, not a regular file";
  if (S_ISFIFO(mode)) return "it is a FIFO, not a regular file";
  if (S_ISSOCK(mode)) return "it is a socket, not a regular file";
  return "it is not a regular file";
}

[[noreturn]] void refuse(const std::string& path, const std::string& what, const std::string& why) {
  throw InputError(fmt::format("{}: cannot read the {}: {}", path, what, why));
}

// Refuses what `st` describes unless it is a regular file of at most max_bytes.
void check_status(const struct stat& st, const std::string& path, const std::string& what, std::uint64_t max_bytes) {
  if (!S_ISREG(st.st_mode)) refuse(path, what, kind_of(st.st_mode));
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes)
    refuse(path, what, fmt::format("{} bytes, more than the limit of {} bytes", st.st_size, max_bytes));
}

class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

void check_input_file(const std::string& path, const std::string& what, std::uint64_t max_bytes) {
  struct stat st{};
  if (::stat(path.c_str(), &st) == 0) check_status(st, path, what, max_bytes);
}

std::string read_text_file(const std::string& path, const std::string& what, std::uint64_t max_bytes) {
  // Checked before opening (opening a device can have effects of its own), and again on
  // the file opened, which is what is read. O_NONBLOCK: opening a FIFO does not wait for
  // a writer.
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) refuse(path, what, std::strerror(errno));
  check_status(st, path, what, max_bytes);
  const Descriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY));
  if (fd.get() < 0) refuse(path, what, std::strerror(errno));
  if (::fstat(fd.get(), &st) != 0) refuse(path, what, std::strerror(errno));
  check_status(st, path, what, max_bytes);
  std::string text(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t done = 0;
  for (;;) {
    // A file that grows while it is read is read up to one byte beyond the limit.
    if (done == text.size()) {
      if (text.size() > max_bytes) refuse(path, what, fmt::format("more than the limit of {} bytes", max_bytes));
      text.resize(std::min<std::uint64_t>(max_bytes + 1, std::max<std::size_t>(2 * text.size(), 4096)));
    }
    const ssize_t n = ::read(fd.get(), text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) refuse(path, what, std::strerror(errno));
    if (n == 0) break;
    done += static_cast<std::size_t>(n);
  }
  text.resize(done);
  return text;
}

}  // namespace ballagg
