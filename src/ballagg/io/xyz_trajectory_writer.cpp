#include "ballagg/io/xyz_trajectory_writer.hpp"

#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/xyz.hpp"

namespace fs = std::filesystem;

namespace ballagg {

template <int D>
XyzTrajectoryWriter<D>::XyzTrajectoryWriter(const std::string& path, const Particles<D>& particles)
    : target_(path),
      temporary_(temporary_path_for(path)),
      particles_(particles),
      out_(temporary_, std::ios::binary | std::ios::trunc) {
  if (!out_) throw std::runtime_error(fmt::format("{}: cannot create the file", temporary_));
}

template <int D>
XyzTrajectoryWriter<D>::~XyzTrajectoryWriter() {
  if (finished_) return;
  out_.close();
  std::error_code ec;
  fs::remove(temporary_, ec);
}

template <int D>
void XyzTrajectoryWriter<D>::write(const Frame<D>& frame) {
  text_.clear();
  append_xyz_frame(text_, frame, particles_);
  out_.write(text_.data(), static_cast<std::streamsize>(text_.size()));
  if (!out_) throw std::runtime_error(fmt::format("{}: cannot write (disk full?)", target_));
}

template <int D>
void XyzTrajectoryWriter<D>::finish() {
  out_.close();
  if (!out_) throw std::runtime_error(fmt::format("{}: cannot write (disk full?)", target_));
  rename_into_place(temporary_, target_);
  finished_ = true;
}

template class XyzTrajectoryWriter<2>;
template class XyzTrajectoryWriter<3>;

}  // namespace ballagg
