#include "ballagg/io/xyz_trajectory_writer.hpp"

#include <filesystem>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/xyz.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {

// The temporary file of a checkpointed run (taken back from `path` if the run was killed
// after completing it), checked to hold the `mark` bytes the checkpoint saw. Throws
// InputError.
std::uint64_t checked_mark(const std::string& path, std::uint64_t mark) {
  check_output_path(path);
  reclaim_completed_file(path);
  const std::string temporary = temporary_path_for(path);
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(temporary, ec);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw InputError(fmt::format("{}: the trajectory of the checkpointed run is not a regular file (cannot resume it)",
                                 temporary));
  const std::uintmax_t size = fs::file_size(temporary, ec);
  if (ec || size < mark)
    throw InputError(fmt::format("{}: the trajectory of the checkpointed run is {} (cannot resume it)", temporary,
                                 ec ? "missing" : "shorter than at the checkpoint"));
  return mark;
}

}  // namespace

template <int D>
XyzTrajectoryWriter<D>::XyzTrajectoryWriter(const std::string& path, const Particles<D>& particles)
    : file_(path), particles_(particles) {}

template <int D>
XyzTrajectoryWriter<D>::XyzTrajectoryWriter(const std::string& path, const Particles<D>& particles, std::uint64_t mark)
    : file_(path, checked_mark(path, mark)), particles_(particles), bytes_(mark) {}

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
