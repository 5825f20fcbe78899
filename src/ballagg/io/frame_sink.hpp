#pragma once
// Where trajectory frames go: a file format (H5MD, extended XYZ) or a test's memory.
#include <cstdint>

#include "ballagg/io/frame.hpp"

namespace ballagg {

template <int D>
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void write(const Frame<D>& frame) = 0;
  // Completes the output (a file is closed and renamed into place). A sink destroyed
  // without finish() leaves nothing behind.
  virtual void finish() = 0;
  // Checkpoints: makes everything written so far durable and returns a mark of how much
  // that is (bytes, frames: the sink's own measure). From then on, a sink destroyed
  // without finish() keeps its temporary file: a run resumed from the checkpoint reopens
  // it cut back to the mark (the writers' resume constructors).
  virtual std::uint64_t flush() = 0;
};

}  // namespace ballagg
