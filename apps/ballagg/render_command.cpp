#include "render_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"
#include "ballagg/core/progress_line.hpp"
#include "ballagg/io/h5md_reader.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/render/picture.hpp"
#include "ballagg/render/pov_scene.hpp"
#include "ballagg/render/video.hpp"
#include "ballagg/run/run_directory.hpp"

namespace fs = std::filesystem;

namespace ballagg::cli {

void add_render_command(CLI::App& app, RenderCommand& render) {
  RenderArgs& a = render.args;
  CLI::App* cmd = render.command = app.add_subcommand(
      "render", "Draw a run: PNG/SVG pictures (2D discs, 3D shaded spheres), a POV-Ray scene, a video");
  cmd->add_option("run_dir", a.run_dir, "Directory of a finished run (the --out of ballagg run)")->required();
  cmd->add_option("--frame", a.frame, "Draw frame K of trajectory.h5md (0 = the initial state; default: final.csv)")
      ->type_name("K");
  cmd->add_option("--png", a.png, "Write a PNG picture (default, if no output is given: RUN_DIR/final.png or frame-K.png)")
      ->type_name("FILE");
  cmd->add_option("--svg", a.svg, "Write an SVG picture")->type_name("FILE");
  cmd->add_option("--pov", a.pov, "3D: write a POV-Ray scene of one aggregate (the largest unless --aggregate)")
      ->type_name("FILE");
  cmd->add_option("--video", a.video, "Write an MP4 video, one frame per snapshot of trajectory.h5md (uses ffmpeg)")
      ->type_name("FILE.mp4");
  cmd->add_option("--width", a.width, "Picture or video width in pixels (64 to 16384, 3D: to 4096; default 1200)")->type_name("PIXELS");
  cmd->add_option("--fps", a.fps, "Video frames per second (default 10)")->type_name("RATE");
  cmd->add_option("--aggregate", a.aggregate,
                  "Draw only the K-th largest cluster (1 = the largest), in one piece across periodic faces")
      ->type_name("K");
  cmd->add_option("--view", a.view, "3D: direction from the scene to the camera (default 1,-1.6,1)")
      ->delimiter(',')
      ->expected(3)
      ->type_name("X,Y,Z");
  cmd->add_option("--light", a.light, "3D: light direction in the picture (x right, y up, z to the viewer; default -0.45,0.6,0.75)")
      ->delimiter(',')
      ->expected(3)
      ->type_name("X,Y,Z");
  cmd->add_flag("--quiet,-q", a.quiet, "No progress of a video's frames on stderr");
}

namespace {

// Checks that `path` can be created (its directory exists and is writable) before any
// work is done, so that a bad name costs nothing and leaves nothing.
void check_writable(const std::string& option, const std::string& path) {
  const fs::path p(path);
  std::error_code ec;
  if (fs::is_directory(p, ec)) throw InputError(fmt::format("{} {}: is a directory (give a file name)", option, path));
  check_output_path(path);  // a device, FIFO, socket or link there is refused before any work
  const std::string probe = fresh_temporary_for(path + ".probe");
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (f == nullptr) throw InputError(fmt::format("{} {}: cannot write: {}", option, path, std::strerror(errno)));
  std::fclose(f);
  fs::remove(probe, ec);
}

void check_extension(const std::string& option, const std::string& path, const std::string& extension) {
  if (!path.empty() && fs::path(path).extension() != extension)
    throw InputError(fmt::format("{} {}: the file name must end in {}", option, path, extension));
}

Vec<3> direction(const std::string& option, const std::vector<double>& v, const Vec<3>& fallback) {
  if (v.empty()) return fallback;
  const Vec<3> d(v[0], v[1], v[2]);
  if (!d.allFinite() || d.norm() == 0.0)
    throw InputError(fmt::format("{} {},{},{}: must be a non-zero direction", option, v[0], v[1], v[2]));
  return d;
}

// "frames 12 / 40  3.1 s" on stderr, as a bar on a terminal (core/progress_line.hpp):
// every so often while the frames are drawn, and once the video is written.
class FrameProgress {
 public:
  FrameProgress(bool quiet, int frames) : quiet_(quiet), frames_(frames), line_(stderr, isatty(STDERR_FILENO) != 0) {}
  void drawn(int frame) {
    if (!quiet_ && line_.due()) report(frame, false);
  }
  void finished() {
    if (!quiet_) report(frames_, true);
  }

 private:
  void report(int drawn, bool final) {
    // "100%" only once ffmpeg has written the video.
    const double done = frames_ == 0 ? 1.0 : std::min(final ? 1.0 : 0.99, static_cast<double>(drawn) / frames_);
    line_.draw(done, fmt::format("frames {} / {}  {:.1f} s", drawn, frames_, line_.seconds()), final);
  }

  bool quiet_;
  int frames_;
  ProgressLine line_;
};

// An MP4 video of every frame of the trajectory; returns what it wrote, for the last lines.
template <int D>
std::string write_video(const RenderArgs& a, const std::string& trajectory, const PictureOptions& options) {
  const int rank = a.aggregate.value_or(0);
  const H5mdReader<D> reader(trajectory);
  const Layout layout = make_layout(a.width);
  FfmpegVideo video(a.video, layout.width, layout.height, a.fps);
  FrameProgress progress(a.quiet, reader.frames());
  for (int k = 0; k < reader.frames(); ++k) {
    cairo_surface_t* image = render_image(make_scene(reader.frame(k), reader.particles(), rank), options);
    try {
      video.add(image);
    } catch (...) {
      cairo_surface_destroy(image);
      throw;
    }
    cairo_surface_destroy(image);
    progress.drawn(k + 1);
  }
  video.finish();
  progress.finished();
  return fmt::format("{} ({} frames)", a.video, reader.frames());
}

template <int D>
int render(const RenderArgs& a, const RunDirectory& run) {
  PictureOptions options;
  options.width = a.width;
  if constexpr (D == 3) {
    options.view.towards_viewer = direction("--view", a.view, options.view.towards_viewer);
    options.view.light = direction("--light", a.light, options.view.light);
  }
  const int rank = a.aggregate.value_or(0);
  const std::string trajectory = run.path("trajectory.h5md");
  std::vector<std::string> written;

  if (!a.video.empty()) written.push_back(write_video<D>(a, trajectory, options));

  const bool picture = !a.png.empty() || !a.svg.empty() || !a.pov.empty() || a.video.empty();
  if (picture) {
    Frame<D> frame;
    Particles<D> particles;
    if (a.frame) {
      const H5mdReader<D> reader(trajectory);
      frame = reader.frame(*a.frame);
      particles = reader.particles();
    } else {
      read_final_state<D>(run, frame, particles);
    }
    std::string png = a.png;
    if (png.empty() && a.svg.empty() && a.pov.empty())
      png = run.path(a.frame ? fmt::format("frame-{}.png", *a.frame) : "final.png");
    if (!png.empty() || !a.svg.empty()) {
      const Scene<D> scene = make_scene(frame, particles, rank);
      if (!png.empty()) {
        write_png(scene, options, png);
        written.push_back(png);
      }
      if (!a.svg.empty()) {
        write_svg(scene, options, a.svg);
        written.push_back(a.svg);
      }
    }
    if constexpr (D == 3) {
      if (!a.pov.empty()) {
        const Scene<3> aggregate = make_scene(frame, particles, rank > 0 ? rank : 1);
        const fs::path p(a.pov);
        write_file_atomically(p.parent_path().empty() ? "." : p.parent_path().string(), p.filename().string(),
                              pov_scene_text(aggregate, options.view));
        written.push_back(fmt::format("{} (render: povray +W{} +H{} +A0.3 {})", a.pov, a.width, a.width, a.pov));
      }
    }
  }
  for (const std::string& w : written) fmt::print("wrote {}\n", w);
  return 0;
}

}  // namespace

int run_render_command(const RenderCommand& command) {
  const RenderArgs& a = command.args;
  if (a.width < kMinPictureWidth || a.width > kMaxPictureWidth)
    throw InputError(fmt::format("--width {}: must be from {} to {} pixels", a.width, kMinPictureWidth, kMaxPictureWidth));
  if (!(a.fps > 0.0 && a.fps <= 240.0)) throw InputError(fmt::format("--fps {}: must be a number in (0, 240]", a.fps));
  if (a.frame && *a.frame < 0) throw InputError(fmt::format("--frame {}: must be 0 or more", *a.frame));
  if (a.aggregate && *a.aggregate < 1)
    throw InputError(fmt::format("--aggregate {}: must be 1 (the largest cluster) or more", *a.aggregate));
  if (a.frame && !a.video.empty())
    throw InputError("--frame and --video: a video shows every frame (give one or the other)");
  check_extension("--png", a.png, ".png");
  check_extension("--svg", a.svg, ".svg");
  check_extension("--pov", a.pov, ".pov");
  check_extension("--video", a.video, ".mp4");
  const RunDirectory run = open_run_directory(a.run_dir);
  const int dimension = run.config.system.dimension;
  if (dimension == 3 && a.width > kMaxSpherePictureWidth)
    throw InputError(fmt::format("--width {}: 3D pictures must be from {} to {} pixels (the depth buffer of a wider one "
                                 "would not fit in memory)", a.width, kMinPictureWidth, kMaxSpherePictureWidth));
  if (dimension == 2) {
    if (!a.pov.empty()) throw InputError(fmt::format("--pov: POV-Ray scenes are for 3D runs ({} is 2D)", a.run_dir));
    if (!a.view.empty()) throw InputError(fmt::format("--view: only for 3D runs ({} is 2D)", a.run_dir));
    if (!a.light.empty()) throw InputError(fmt::format("--light: only for 3D runs ({} is 2D)", a.run_dir));
  }
  for (const auto& [option, path] : {std::pair{"--png", a.png}, {"--svg", a.svg}, {"--pov", a.pov}, {"--video", a.video}})
    if (!path.empty()) check_writable(option, path);
  return dimension == 2 ? render<2>(a, run) : render<3>(a, run);
}

}  // namespace ballagg::cli
