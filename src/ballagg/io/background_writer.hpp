#pragma once
// Writes trajectory frames on a thread of its own, so that the run pays only for copying
// what a frame is computed from (capture_source: a few memcpy's); computing positions,
// labels and images (assemble_frame), encoding and writing overlap with the simulation.
// Sources are recycled (no allocation, no page faults after the first frames). Frames wait
// in a queue bounded by memory, not by a count: the sources in existence hold at most
// `memory_budget` bytes (but one frame is always allowed, however large), so that many
// small frames can be in flight and a few huge ones cannot exhaust the memory. A run
// faster than the disk waits for a free source. An error in the writer thread is rethrown
// to the run at its next call.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "ballagg/io/frame_sink.hpp"

namespace ballagg {

// The default memory budget of the frames in flight: at N = 10^6 a 2D frame's source
// holds 20 to 56 MB (offsets and cluster ids, then origin and velocity per live cluster),
// so four to twelve such frames.
inline constexpr std::size_t kFrameQueueBytes = std::size_t{256} << 20;

template <int D>
class BackgroundWriter {
 public:
  explicit BackgroundWriter(std::vector<std::unique_ptr<FrameSink<D>>> sinks,
                            std::size_t memory_budget = kFrameQueueBytes);
  ~BackgroundWriter();  // stops the thread; unfinished sinks leave nothing behind
  BackgroundWriter(const BackgroundWriter&) = delete;
  BackgroundWriter& operator=(const BackgroundWriter&) = delete;

  // A source to fill (waits while the budget is spent and every source is queued), then
  // queue it with submit().
  FrameSource<D>& acquire();
  void submit();
  // Writes what is queued and completes every sink.
  void finish();
  // Writes what is queued, then flushes every sink (FrameSink::flush): their marks.
  std::vector<std::uint64_t> flush();

  // Sources allocated so far: how many frames were ever in flight at once (tests).
  int sources() const;

 private:
  struct Slot {
    std::unique_ptr<FrameSource<D>> source;
    std::size_t bytes = 0;  // source->bytes() when it was last submitted
  };
  void drain();
  void stop();

  std::vector<std::unique_ptr<FrameSink<D>>> sinks_;
  const std::size_t budget_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Slot> free_;
  Slot filling_;
  std::deque<Slot> queue_;
  bool writing_ = false;        // the writer thread holds a source
  std::size_t held_ = 0;        // bytes of every source allocated (free, filling, queued, being written)
  std::size_t frame_bytes_ = 0; // bytes of the last submitted source: what the next will need
  int sources_ = 0;
  bool closing_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace ballagg
