#pragma once
// trajectory.xyz: extended XYZ frames one after the other (OVITO and ASE read every frame).
#include <string>

#include "ballagg/io/atomic_file.hpp"
#include "ballagg/io/frame_sink.hpp"

namespace ballagg {

template <int D>
class XyzTrajectoryWriter final : public FrameSink<D> {
 public:
  // Writes to a temporary file next to `path`, renamed to `path` by finish(). Every
  // failure to write throws OutputError naming `path`.
  XyzTrajectoryWriter(const std::string& path, const Particles<D>& particles);
  // A resumed run: continues the temporary file left by a checkpointed one, cut back to
  // `mark` bytes (what flush() returned). Throws InputError if it is missing or shorter.
  XyzTrajectoryWriter(const std::string& path, const Particles<D>& particles, std::uint64_t mark);
  void write(const Frame<D>& frame) override;
  void finish() override;
  std::uint64_t flush() override;  // the mark: bytes written

 private:
  AtomicFile file_;  // removes the temporary file unless finished or a checkpoint refers to it
  Particles<D> particles_;
  std::string text_;  // one frame's text, reused
  std::uint64_t bytes_ = 0;
};

}  // namespace ballagg
