#include "ballagg/io/xyz_trajectory_writer.hpp"

#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/xyz.hpp"

namespace ballagg {

template <int D>
XyzTrajectoryWriter<D>::XyzTrajectoryWriter(const std::string& path, const Particles<D>& particles)
    : file_(path), particles_(particles) {}

template <int D>
XyzTrajectoryWriter<D>::XyzTrajectoryWriter(const std::string& path, const Particles<D>& particles, std::uint64_t mark)
    : file_(path, checked_temporary_size(path, mark)), particles_(particles), bytes_(mark) {}

template <int D>
void XyzTrajectoryWriter<D>::write(const Frame<D>& frame) {
  text_.clear();
  append_xyz_frame(text_, frame, particles_);
  file_.write(text_);
  bytes_ += text_.size();
}

template <int D>
void XyzTrajectoryWriter<D>::finish() {
  file_.commit();
}

template <int D>
std::uint64_t XyzTrajectoryWriter<D>::flush() {
  file_.keep();  // every write went to the file already (no buffer of ours)
  return bytes_;
}

template class XyzTrajectoryWriter<2>;
template class XyzTrajectoryWriter<3>;

}  // namespace ballagg
