#include "ballagg/render/video.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/output_error.hpp"

extern char** environ;

namespace ballagg {
namespace {

// What write_failure_at tries to add to a video ffmpeg failed to write: more than ffmpeg
// writes at once (its I/O buffer is 32 KiB), so that a disk that took ffmpeg's last bytes
// but not the next ones cannot take these either.
constexpr std::size_t kProbeBytes = std::size_t{1} << 20;

// Why ffmpeg could not write `temporary`: an errno value, or 0 if writing is not the cause.
// ffmpeg says why only in a message ("Error writing trailer of F: No space left on
// device"), so we write where it failed ourselves, kProbeBytes at the end of the file and
// fsync, and keep our own errno: ENOSPC, EDQUOT, EFBIG, EIO, or ENOENT if the directory
// has gone. A file-size limit is compared instead of written into (a write beyond it
// raises SIGXFSZ, which ends a process that does not ignore it).
int write_failure_at(const std::string& temporary) {
  const int fd = open(temporary.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return errno;
  int error = 0;
  struct stat status {};
  rlimit size_limit{};
  if (fstat(fd, &status) != 0) {
    error = errno;
  } else if (getrlimit(RLIMIT_FSIZE, &size_limit) == 0 && size_limit.rlim_cur != RLIM_INFINITY &&
             static_cast<rlim_t>(status.st_size) + kProbeBytes > size_limit.rlim_cur) {
    error = EFBIG;
  } else {
    const std::vector<char> zeros(kProbeBytes, 0);
    for (std::size_t done = 0; done < zeros.size() && error == 0;) {
      const ssize_t n = write(fd, zeros.data() + done, zeros.size() - done);
      if (n > 0)
        done += static_cast<std::size_t>(n);
      else if (n == 0 || errno != EINTR)
        error = n == 0 ? EIO : errno;
    }
    if (error == 0 && fsync(fd) != 0) error = errno;
  }
  if (close(fd) != 0 && error == 0) error = errno;
  return error;
}

// The last line of `text` that is not blank; empty if there is none.
std::string last_line(const std::string& text) {
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last;
}

}  // namespace

FfmpegVideo::FfmpegVideo(const std::string& path, int width, int height, double fps)
    : path_(path), temporary_(fresh_temporary_for(path)), width_(width), height_(height) {
  // A write to ffmpeg after it died must fail with EPIPE, not kill us.
  signal(SIGPIPE, SIG_IGN);
  // ffmpeg's messages go to memory: nothing but the video is written next to it, and a
  // full disk cannot swallow them.
  log_fd_ = memfd_create("ffmpeg-log", MFD_CLOEXEC);
  if (log_fd_ < 0) throw std::runtime_error(fmt::format("--video: cannot start ffmpeg: {}", std::strerror(errno)));
  int fds[2];
  if (pipe(fds) != 0) {
    const int error = errno;
    close(log_fd_);
    throw std::runtime_error(fmt::format("--video: cannot start ffmpeg: {}", std::strerror(error)));
  }
  // -xerror: an error ends ffmpeg with a nonzero status. Without it ffmpeg 5.1 exits with 0
  // when the trailer cannot be written (a full disk), leaving a truncated file.
  const std::vector<std::string> args{
      "ffmpeg", "-nostdin", "-hide_banner", "-loglevel", "error", "-xerror", "-y",
      "-f", "rawvideo", "-pixel_format", "bgra", "-video_size", fmt::format("{}x{}", width, height),
      "-framerate", fmt::format("{}", fps), "-i", "-",
      "-c:v", "libx264", "-preset", "medium", "-crf", "20", "-pix_fmt", "yuv420p",
      "-movflags", "+faststart", "-f", "mp4", temporary_};
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
  posix_spawn_file_actions_addclose(&actions, fds[1]);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, log_fd_, 2);
  const int status = posix_spawnp(&pid_, "ffmpeg", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[0]);
  if (status != 0) {
    close(fds[1]);
    close(log_fd_);
    pid_ = -1;
    throw std::runtime_error(status == ENOENT ? std::string("--video: ffmpeg not found (install the Debian package ffmpeg)")
                                              : fmt::format("--video: cannot start ffmpeg: {}", std::strerror(status)));
  }
  pipe_ = fdopen(fds[1], "wb");
}

FfmpegVideo::~FfmpegVideo() {
  if (pid_ > 0) abort();
  if (log_fd_ >= 0) close(log_fd_);
}

void FfmpegVideo::abort() {
  if (pipe_) std::fclose(pipe_);
  pipe_ = nullptr;
  if (pid_ > 0) {
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  pid_ = -1;
  std::error_code ec;
  std::filesystem::remove(temporary_, ec);
}

std::string FfmpegVideo::log() const {
  std::string text;
  char buffer[4096];
  for (off_t offset = 0;;) {
    const ssize_t n = pread(log_fd_, buffer, sizeof buffer, offset);
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    offset += n;
  }
  return text;
}

int FfmpegVideo::wait_for_ffmpeg() {
  if (pipe_) std::fclose(pipe_);
  pipe_ = nullptr;
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  return status;
}

void FfmpegVideo::fail(int wait_status, const char* what) {
  std::string why = last_line(log());
  if (why.empty()) why = "no message";
  const int error = WIFSIGNALED(wait_status) && WTERMSIG(wait_status) == SIGXFSZ ? EFBIG : write_failure_at(temporary_);
  std::error_code ec;
  std::filesystem::remove(temporary_, ec);
  if (error != 0) throw_output_error(path_, error);
  throw std::runtime_error(fmt::format("{}: ffmpeg {}: {}", path_, what, why));
}

void FfmpegVideo::add(cairo_surface_t* image) {
  cairo_surface_flush(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  const int stride = cairo_image_surface_get_stride(image);
  if (cairo_image_surface_get_width(image) != width_ || cairo_image_surface_get_height(image) != height_)
    throw std::logic_error("video frame of the wrong size");
  // Cairo's ARGB32 is a native-endian 32-bit word: B, G, R, A in memory on x86-64.
  for (int y = 0; y < height_; ++y) {
    // A short write: ffmpeg has ended (EPIPE), and says why in its status and messages.
    if (std::fwrite(data + static_cast<std::ptrdiff_t>(y) * stride, 4, width_, pipe_) != static_cast<std::size_t>(width_))
      fail(wait_for_ffmpeg(), "stopped");
  }
}

void FfmpegVideo::finish() {
  const bool flushed = std::fflush(pipe_) == 0;
  const int status = wait_for_ffmpeg();
  // ffmpeg logs errors only: a message is a failure even with status 0.
  const bool ok = flushed && WIFEXITED(status) && WEXITSTATUS(status) == 0 && last_line(log()).empty();
  if (!ok) fail(status, "failed");
  rename_into_place(temporary_, path_);
}

}  // namespace ballagg
