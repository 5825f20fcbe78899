#pragma once
// Where trajectory frames go: a file format (H5MD, extended XYZ) or a test's memory.
#include <cstdint>
#include <functional>

#include "ballagg/io/frame.hpp"

namespace ballagg {

template <int D>
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void write(const Frame<D>& frame) = 0;
  // The frame `source` describes (BackgroundWriter's thread). `assembled` returns it as a
  // Frame, assembled once for all the sinks that ask. The default writes that; a sink can
  // instead assemble only what it stores, piece by piece (H5mdWriter).
  virtual void write_source(const FrameSource<D>& source, const std::function<const Frame<D>&()>& assembled) {
    (void)source;
    write(assembled());
  }
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
