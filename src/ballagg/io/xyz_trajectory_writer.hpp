#pragma once
// trajectory.xyz: extended XYZ frames one after the other (OVITO and ASE read every frame).
#include <fstream>
#include <string>

#include "ballagg/io/frame_sink.hpp"

namespace ballagg {

template <int D>
class XyzTrajectoryWriter final : public FrameSink<D> {
 public:
  // Writes to a temporary file next to `path`, renamed to `path` by finish().
  XyzTrajectoryWriter(const std::string& path, const Particles<D>& particles);
  ~XyzTrajectoryWriter() override;
  void write(const Frame<D>& frame) override;
  void finish() override;

 private:
  std::string target_, temporary_;
  Particles<D> particles_;
  std::ofstream out_;
  std::string text_;  // one frame's text, reused
  bool finished_ = false;
};

}  // namespace ballagg
