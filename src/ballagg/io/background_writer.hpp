#pragma once
// Writes trajectory frames on a thread of its own, so that the run pays only for copying
// what a frame is computed from (capture_source: a few memcpy's); computing positions,
// labels and images (assemble_frame), encoding and writing overlap with the simulation.
// `capacity` sources are recycled (no allocation, no page faults after the first frames):
// a run faster than the disk waits for a free one. An error in the writer thread is
// rethrown to the run at its next call.
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "ballagg/io/frame_sink.hpp"

namespace ballagg {

template <int D>
class BackgroundWriter {
 public:
  explicit BackgroundWriter(std::vector<std::unique_ptr<FrameSink<D>>> sinks, int capacity = 4);
  ~BackgroundWriter();  // stops the thread; unfinished sinks leave nothing behind
  BackgroundWriter(const BackgroundWriter&) = delete;
  BackgroundWriter& operator=(const BackgroundWriter&) = delete;

  // A free source to fill (waits while all are queued), then queue it with submit().
  FrameSource<D>& acquire();
  void submit();
  // Writes what is queued and completes every sink.
  void finish();

 private:
  void drain();
  void stop();

  std::vector<std::unique_ptr<FrameSink<D>>> sinks_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::unique_ptr<FrameSource<D>>> free_;
  std::unique_ptr<FrameSource<D>> filling_;
  std::deque<std::unique_ptr<FrameSource<D>>> queue_;
  bool closing_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace ballagg
