// What one trajectory frame costs at large N, phase by phase: the copy the run pays for
// (capture_source, on the simulation's thread), and the work of the writer thread
// (assemble_frame, H5MD write, XYZ write). The state is a 2D or 3D initial state (every
// sphere its own cluster: the most expensive case for the per-cluster loop).
// Run: build/bin/ballagg_snapshot_costs [N] [dimension] [frames] [dir]
#include <chrono>
#include <cstdio>
#include <filesystem>
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
  H5mdWriter<D> h5md(dir + "/bench.h5md", particles_of(s), to_toml_text(c));
  double capture = 1e300, assemble = 1e300, write = 1e300, xyz = 1e300, write_total = 0.0;
  for (int k = 0; k < frames; ++k) {
    auto t0 = clock_type::now();
    capture_source(s, 0.5 * k, k, false, source);
    capture = std::min(capture, seconds_since(t0));
    t0 = clock_type::now();
    assemble_frame(source, frame);
    assemble = std::min(assemble, seconds_since(t0));
    t0 = clock_type::now();
    h5md.write(frame);
    write = std::min(write, seconds_since(t0));
    write_total += seconds_since(t0);
  }
  h5md.finish();
  {
    XyzTrajectoryWriter<D> writer(dir + "/bench.xyz", particles_of(s));
    for (int k = 0; k < 3; ++k) {
      const auto t0 = clock_type::now();
      writer.write(frame);
      xyz = std::min(xyz, seconds_since(t0));
    }
    writer.finish();
  }
  const double h5md_mb = std::filesystem::file_size(dir + "/bench.h5md") / 1e6 / frames;
  const double xyz_mb = std::filesystem::file_size(dir + "/bench.xyz") / 1e6 / 3;
  std::printf("%dD N=%lld: capture_source %.1f ms | assemble_frame %.1f ms | H5MD write %.1f ms, mean %.1f ms "
              "(%.1f MB/frame) | XYZ write %.0f ms (%.0f MB/frame)   [min over %d frames; XYZ over 3]\n",
              D, static_cast<long long>(n), 1e3 * capture, 1e3 * assemble, 1e3 * write, 1e3 * write_total / frames,
              h5md_mb, 1e3 * xyz, xyz_mb, frames);
  std::filesystem::remove(dir + "/bench.h5md");
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
