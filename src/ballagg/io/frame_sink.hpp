#pragma once
// Where trajectory frames go: a file format (H5MD, extended XYZ) or a test's memory.
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
};

}  // namespace ballagg
