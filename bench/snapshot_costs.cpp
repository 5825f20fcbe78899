// What one trajectory frame costs at large N, phase by phase: the copy the run pays for
// (capture_source, on the simulation's thread), and the work of the writer thread (the
// H5MD write from the frame's source, in single and double precision; assemble_frame and
// the XYZ write). The state is a 2D or 3D initial state (every sphere its own cluster: the
// most expensive case for the per-cluster loops).
// Run: build/bin/ballagg_snapshot_costs [N] [dimension] [frames] [dir]
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "ballagg/config/config.hpp"
#include "ballagg/initial/initial_state.hpp"
#include "ballagg/io/h5md_writer.hpp"
#include "ballagg/io/xyz_trajectory_writer.hpp"

namespace {

using namespace ballagg;
using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
  return std::chrono::duration<double>(clock_type::now() - t0).count();
}

template <int D>
void measure(std::int64_t n, int frames, const std::string& dir) {
  Config c = parse_config_text("", "bench", {fmt::format("system.dimension={}", D), fmt::format("system.n={}", n),
                                             "system.volume_fraction=0.3"});
  const State<D> s = make_initial_state<D>(c);
  FrameSource<D> source;
  Frame<D> frame;
  LayoutCopies<D> layouts;
  double capture = 1e300, capture_shared = 1e300, assemble = 1e300, xyz = 1e300;
  State<D> changed = s;
  for (int k = 0; k < 3; ++k) {
    // The layout changed since the last frame (copied), then not (shared).
    changed.layout_changed();
    auto t0 = clock_type::now();
    capture_source(changed, 0.5 * k, k, false, source, layouts);
    capture = std::min(capture, seconds_since(t0));
    t0 = clock_type::now();
    capture_source(changed, 0.5 * k, k, false, source, layouts);
    capture_shared = std::min(capture_shared, seconds_since(t0));
    t0 = clock_type::now();
    assemble_frame(source, frame);
    assemble = std::min(assemble, seconds_since(t0));
  }
  // What the writer thread does per frame: H5mdWriter::write_source (assembly block by
  // block, conversion, HDF5 write, page release), in each precision.
  for (const SnapshotPrecision precision : {SnapshotPrecision::single, SnapshotPrecision::double_}) {
    const std::string path = dir + "/bench.h5md";
    double write = 1e300, write_total = 0.0;
    {
      H5mdWriter<D> h5md(path, particles_of(s), to_toml_text(c), precision);
      const auto never = []() -> const Frame<D>& { throw std::logic_error("the H5MD writer assembles by itself"); };
      for (int k = 0; k < frames; ++k) {
        capture_source(s, 0.5 * k, k, false, source, layouts);
        const auto t0 = clock_type::now();
        h5md.write_source(source, never);
        write = std::min(write, seconds_since(t0));
        write_total += seconds_since(t0);
      }
      h5md.finish();
    }
    std::printf("%dD N=%lld, %s: H5MD write_source %.1f ms, mean %.1f ms (%.1f MB/frame)   [min over %d frames]\n", D,
                static_cast<long long>(n), std::string(to_string(precision)).c_str(), 1e3 * write,
                1e3 * write_total / frames, std::filesystem::file_size(path) / 1e6 / frames, frames);
    std::filesystem::remove(path);
  }
  {
    XyzTrajectoryWriter<D> writer(dir + "/bench.xyz", particles_of(s));
    for (int k = 0; k < 3; ++k) {
      const auto t0 = clock_type::now();
      writer.write(frame);
      xyz = std::min(xyz, seconds_since(t0));
    }
    writer.finish();
  }
  const double xyz_mb = std::filesystem::file_size(dir + "/bench.xyz") / 1e6 / 3;
  std::printf("%dD N=%lld: capture_source %.1f ms, %.1f ms with the layout shared (run thread) | assemble_frame %.1f ms "
              "(for XYZ) | XYZ write %.0f ms (%.0f MB/frame)   [min over 3 frames]\n",
              D, static_cast<long long>(n), 1e3 * capture, 1e3 * capture_shared, 1e3 * assemble, 1e3 * xyz, xyz_mb);
  std::filesystem::remove(dir + "/bench.xyz");
}

}  // namespace

int main(int argc, char** argv) {
  const std::int64_t n = argc > 1 ? std::stoll(argv[1]) : 1'000'000;
  const int dimension = argc > 2 ? std::stoi(argv[2]) : 2;
  const int frames = argc > 3 ? std::stoi(argv[3]) : 10;
  const std::string dir = argc > 4 ? argv[4] : std::filesystem::temp_directory_path().string();
  if (dimension == 2) measure<2>(n, frames, dir);
  else measure<3>(n, frames, dir);
}
