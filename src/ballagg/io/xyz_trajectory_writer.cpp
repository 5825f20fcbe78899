#include "ballagg/io/xyz_trajectory_writer.hpp"

#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "ballagg/config/config.hpp"
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
XyzTrajectoryWriter<D>::XyzTrajectoryWriter(const std::string& path, const Particles<D>& particles, std::uint64_t mark)
    : target_(path), temporary_(temporary_path_for(path)), particles_(particles), bytes_(mark), keep_(true) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(temporary_, ec);
  if (ec || size < mark)
    throw InputError(fmt::format("{}: the trajectory of the checkpointed run is {} (cannot resume it)", temporary_,
                                 ec ? "missing" : "shorter than at the checkpoint"));
  fs::resize_file(temporary_, mark);
  out_.open(temporary_, std::ios::binary | std::ios::app);
  if (!out_) throw std::runtime_error(fmt::format("{}: cannot open the file", temporary_));
}

template <int D>
XyzTrajectoryWriter<D>::~XyzTrajectoryWriter() {
  if (finished_ || keep_) return;
  out_.close();
  std::error_code ec;
  fs::remove(temporary_, ec);
}

template <int D>
void XyzTrajectoryWriter<D>::write(const Frame<D>& frame) {
  text_.clear();
  append_xyz_frame(text_, frame, particles_);
  out_.write(text_.data(), static_cast<std::streamsize>(text_.size()));
  bytes_ += text_.size();
  if (!out_) throw std::runtime_error(fmt::format("{}: cannot write (disk full?)", target_));
}

template <int D>
void XyzTrajectoryWriter<D>::finish() {
  out_.close();
  if (!out_) throw std::runtime_error(fmt::format("{}: cannot write (disk full?)", target_));
  rename_into_place(temporary_, target_);
  finished_ = true;
}

template <int D>
std::uint64_t XyzTrajectoryWriter<D>::flush() {
  out_.flush();
  if (!out_) throw std::runtime_error(fmt::format("{}: cannot write (disk full?)", target_));
  keep_ = true;
  return bytes_;
}

template class XyzTrajectoryWriter<2>;
template class XyzTrajectoryWriter<3>;

}  // namespace ballagg
