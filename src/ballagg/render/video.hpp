#pragma once
// A video through ffmpeg (Debian's, found on PATH): raw BGRA frames written to its
// standard input, encoded as H.264 in an MP4 file (yuv420p, so that every player reads
// it). The file is written to a temporary name and renamed by finish(); a video that is
// not finished is removed.
#include <sys/types.h>

#include <cstdio>
#include <string>

#include <cairo.h>

namespace ballagg {

class FfmpegVideo {
 public:
  // Starts ffmpeg. Throws std::runtime_error if it cannot be started.
  FfmpegVideo(const std::string& path, int width, int height, double frames_per_second);
  ~FfmpegVideo();
  FfmpegVideo(const FfmpegVideo&) = delete;
  FfmpegVideo& operator=(const FfmpegVideo&) = delete;

  // One frame: an ARGB32 image surface of the size given.
  void add(cairo_surface_t* image);
  // Waits for ffmpeg; throws with its last error line if it failed.
  void finish();

 private:
  void abort();
  std::string last_log_line() const;

  std::string path_, temporary_, log_;
  int width_, height_;
  pid_t pid_ = -1;
  std::FILE* pipe_ = nullptr;
};

}  // namespace ballagg
