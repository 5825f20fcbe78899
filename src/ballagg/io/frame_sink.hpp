#pragma once
// Where trajectory frames go: a file format (H5MD, extended XYZ) or a test's memory.
#include "ballagg/io/frame.hpp"

namespace ballagg {

template <int D>
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void write(const Frame<D>& frame) = 0;
  // The same, for a frame the caller no longer needs (a queue can keep it without a copy).
  virtual void take(Frame<D>&& frame) { write(frame); }
  // Completes the output (a file is closed and renamed into place). A sink destroyed
  // without finish() leaves nothing behind.
  virtual void finish() = 0;
};

}  // namespace ballagg
