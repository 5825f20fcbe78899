#pragma once
// A video through ffmpeg (Debian's, found on PATH): raw BGRA frames written to its
// standard input, encoded as H.264 in an MP4 file (yuv420p, so that every player reads
// it). The file is written to a temporary name and renamed by finish(); a video that is
// not finished is removed.
//
// A video that cannot be written (a full disk, a file-size limit, a directory that has
// gone) is an OutputError naming it, like every output file (docs/hardening.md). ffmpeg
// reports a failed write only as a message, so the cause is found by writing where it
// failed ourselves (write_failure_at in video.cpp); any other failure of ffmpeg is a
// std::runtime_error with its last message.
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
  // Waits for ffmpeg and renames the video into place; throws if ffmpeg failed.
  void finish();

 private:
  // Closes ffmpeg's input and waits for it to end: its wait status.
  int wait_for_ffmpeg();
  // Throws for a failure of ffmpeg (`what`: "stopped", "failed"), after removing the
  // temporary file.
  [[noreturn]] void fail(int wait_status, const char* what);
  void abort();
  // ffmpeg's messages (it logs errors only), kept in memory.
  std::string log() const;

  std::string path_, temporary_;
  int width_, height_;
  pid_t pid_ = -1;
  std::FILE* pipe_ = nullptr;
  int log_fd_ = -1;
};

}  // namespace ballagg
