#include "ballagg/render/video.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "ballagg/io/output_dir.hpp"

extern char** environ;

namespace ballagg {

FfmpegVideo::FfmpegVideo(const std::string& path, int width, int height, double fps)
    : path_(path), temporary_(temporary_path_for(path)), log_(temporary_path_for(path + ".ffmpeg-log")),
      width_(width), height_(height) {
  // A write to ffmpeg after it died must fail with EPIPE, not kill us.
  signal(SIGPIPE, SIG_IGN);
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error(fmt::format("--video: cannot start ffmpeg: {}", std::strerror(errno)));
  const std::vector<std::string> args{
      "ffmpeg", "-nostdin", "-hide_banner", "-loglevel", "error", "-y",
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
  posix_spawn_file_actions_addopen(&actions, 2, log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const int status = posix_spawnp(&pid_, "ffmpeg", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[0]);
  if (status != 0) {
    close(fds[1]);
    pid_ = -1;
    std::error_code ec;
    std::filesystem::remove(log_, ec);
    throw std::runtime_error(status == ENOENT ? std::string("--video: ffmpeg not found (install the Debian package ffmpeg)")
                                              : fmt::format("--video: cannot start ffmpeg: {}", std::strerror(status)));
  }
  pipe_ = fdopen(fds[1], "wb");
}

FfmpegVideo::~FfmpegVideo() {
  if (pid_ > 0) abort();
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
  std::filesystem::remove(log_, ec);
}

std::string FfmpegVideo::last_log_line() const {
  std::ifstream in(log_);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last.empty() ? "no message" : last;
}

void FfmpegVideo::add(cairo_surface_t* image) {
  cairo_surface_flush(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  const int stride = cairo_image_surface_get_stride(image);
  if (cairo_image_surface_get_width(image) != width_ || cairo_image_surface_get_height(image) != height_)
    throw std::logic_error("video frame of the wrong size");
  // Cairo's ARGB32 is a native-endian 32-bit word: B, G, R, A in memory on x86-64.
  for (int y = 0; y < height_; ++y) {
    if (std::fwrite(data + static_cast<std::ptrdiff_t>(y) * stride, 4, width_, pipe_) != static_cast<std::size_t>(width_)) {
      const std::string why = last_log_line();
      abort();
      throw std::runtime_error(fmt::format("{}: ffmpeg stopped: {}", path_, why));
    }
  }
}

void FfmpegVideo::finish() {
  const bool flushed = std::fclose(pipe_) == 0;
  pipe_ = nullptr;
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  const bool ok = flushed && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  const std::string why = ok ? "" : last_log_line();
  std::error_code ec;
  std::filesystem::remove(log_, ec);
  if (!ok) {
    std::filesystem::remove(temporary_, ec);
    throw std::runtime_error(fmt::format("{}: ffmpeg failed: {}", path_, why));
  }
  rename_into_place(temporary_, path_);
}

}  // namespace ballagg
