#pragma once
// Runs a FrameSink on a thread of its own, so that encoding and writing a frame overlaps
// with the simulation: the engine only pays for capturing the frame. At most `capacity`
// frames wait in memory; a faster producer waits for the writer. An error in the writer
// is rethrown to the producer at its next call.
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
class BackgroundSink final : public FrameSink<D> {
 public:
  BackgroundSink(std::vector<std::unique_ptr<FrameSink<D>>> sinks, int capacity = 2);
  ~BackgroundSink() override;  // stops the thread; unfinished sinks leave nothing behind
  void write(const Frame<D>& frame) override;  // copies the frame
  void take(Frame<D>&& frame) override;
  void finish() override;

 private:
  void drain();
  void stop();

  std::vector<std::unique_ptr<FrameSink<D>>> sinks_;
  int capacity_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Frame<D>> queue_;
  bool closing_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace ballagg
