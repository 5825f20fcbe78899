// Pictures checked by their pixels: discs cover their area fraction, a single disc is
// where it should be, periodic images fill the faces, neighbours differ in colour, 3D
// spheres are shaded, depth-sorted and cut by periodic faces; POV-Ray scenes, videos and
// the `ballagg render` command line with its bad-input contract.
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "ballagg/io/h5md_reader.hpp"
#include "ballagg/io/state_csv.hpp"
#include "ballagg/render/disc_picture.hpp"
#include "ballagg/render/picture.hpp"
#include "ballagg/render/pov_scene.hpp"
#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {

using testing::TempDir;

struct Pixel {
  int r, g, b;
};

// An ARGB32 (opaque) cairo image surface, read pixel by pixel.
class Raster {
 public:
  explicit Raster(cairo_surface_t* s) : surface_(s) { cairo_surface_flush(s); }
  static Raster from_png(const std::string& path) { return Raster(cairo_image_surface_create_from_png(path.c_str())); }
  ~Raster() { cairo_surface_destroy(surface_); }
  Raster(const Raster&) = delete;
  bool ok() const { return cairo_surface_status(surface_) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface_); }
  int height() const { return cairo_image_surface_get_height(surface_); }
  Pixel at(int x, int y) const {
    const unsigned char* row = cairo_image_surface_get_data(surface_) + y * cairo_image_surface_get_stride(surface_);
    const std::uint32_t p = reinterpret_cast<const std::uint32_t*>(row)[x];
    return {static_cast<int>((p >> 16) & 0xff), static_cast<int>((p >> 8) & 0xff), static_cast<int>(p & 0xff)};
  }
  bool white(int x, int y) const {
    const Pixel p = at(x, y);
    return p.r > 250 && p.g > 250 && p.b > 250;
  }

 private:
  cairo_surface_t* surface_;
};

template <int D>
struct Picture {
  Frame<D> frame;
  Particles<D> particles;
  void add(const Vec<D>& x, double radius, int cluster) {
    frame.position.push_back(x);
    frame.velocity.push_back(Vec<D>::Zero());
    frame.cluster.push_back(cluster);
    particles.radius.push_back(radius);
    particles.mass.push_back(1.0);
  }
};

constexpr int kWidth = 800;

// The red of the largest cluster, as 8-bit channels.
Pixel largest_red() {
  const Rgb& c = kClusterColours[0];
  return {static_cast<int>(std::lround(255 * c.r)), static_cast<int>(std::lround(255 * c.g)),
          static_cast<int>(std::lround(255 * c.b))};
}

// A pixel counts as disc when its green channel is past halfway from white to the red's
// (antialiased edge pixels are counted when more than half covered).
bool reddish(const Pixel& p) { return p.g < (255 + largest_red().g) / 2 && p.r > p.g + 60; }

TEST(Render2D, DiscsCoverTheirAreaFractionPeriodicImagesIncluded) {
  Picture<2> p;
  p.particles.box = {20.0, Boundary::periodic};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(0.0, 20.0);
  const double r = 0.6;
  int straddling = 0;
  while (p.frame.size() < 110) {  // area fraction 0.31
    const Vec<2> x(coordinate(rng), coordinate(rng));
    bool free = true;
    for (const Vec<2>& y : p.frame.position) free = free && p.particles.box.separation(x, y).norm() > 2 * r;
    if (!free) continue;
    p.add(x, r, 0);  // one cluster: every disc in the same red
    straddling += x[0] < r || x[0] > 20 - r || x[1] < r || x[1] > 20 - r;
  }
  ASSERT_GT(straddling, 10);
  const double area_fraction = p.frame.size() * std::numbers::pi * r * r / (20.0 * 20.0);
  const Raster image(render_image(make_scene(p.frame, p.particles), {kWidth, {}}));
  const Layout l = make_layout(kWidth);
  int inside = 0, total = 0;
  for (int y = static_cast<int>(l.margin); y < static_cast<int>(l.margin + l.side); ++y)
    for (int x = static_cast<int>(l.margin); x < static_cast<int>(l.margin + l.side); ++x, ++total)
      inside += reddish(image.at(x, y));
  EXPECT_NEAR(static_cast<double>(inside) / total, area_fraction, 0.02 * area_fraction);
}

TEST(Render2D, ASingleRedDiscAppearsWhereItShould) {
  Picture<2> p;
  p.particles.box = {10.0, Boundary::walls};
  p.add(Vec<2>(3.0, 7.0), 0.8, 0);
  const Raster image(render_image(make_scene(p.frame, p.particles), {kWidth, {}}));
  const Layout l = make_layout(kWidth);
  const double k = l.side / 10.0;  // pixels per unit
  const double cx = l.margin + 3.0 * k, cy = l.margin + l.side - 7.0 * k;  // y up
  double sx = 0, sy = 0;
  int count = 0;
  // In the panel (the caption's legend has a red swatch too).
  for (int y = 0; y < static_cast<int>(l.caption_top); ++y)
    for (int x = 0; x < image.width(); ++x)
      if (reddish(image.at(x, y))) {
        sx += x + 0.5, sy += y + 0.5;
        ++count;
      }
  ASSERT_GT(count, 0);
  EXPECT_NEAR(sx / count, cx, 0.5);
  EXPECT_NEAR(sy / count, cy, 0.5);
  EXPECT_NEAR(count, std::numbers::pi * std::pow(0.8 * k, 2), 0.02 * std::numbers::pi * std::pow(0.8 * k, 2));
  const Pixel centre = image.at(static_cast<int>(cx), static_cast<int>(cy));
  EXPECT_EQ(centre.r, largest_red().r);
  EXPECT_EQ(centre.g, largest_red().g);
  EXPECT_EQ(centre.b, largest_red().b);
}

TEST(Render2D, TouchingClustersNeverShareAColourAndTheLargestIsRed) {
  Picture<2> p;
  p.particles.box = {40.0, Boundary::walls};
  for (int k = 0; k < 12; ++k) p.add(Vec<2>(2.0 + k * 1.0, 5.0), 0.5, k);  // a row of touching monomers
  for (int k = 0; k < 20; ++k) p.add(Vec<2>(2.0 + k * 1.0, 20.0), 0.5, 12);  // the largest cluster
  const int largest = kth_largest_cluster(p.frame.cluster, 1);
  ASSERT_EQ(largest, 12);
  const std::vector<std::uint8_t> colour = cluster_colours(p.frame, p.particles, largest);
  for (int k = 12; k < 32; ++k) EXPECT_EQ(colour[k], 0);
  for (int k = 0; k < 12; ++k) EXPECT_NE(colour[k], 0);
  for (int k = 0; k + 1 < 12; ++k) EXPECT_NE(colour[k], colour[k + 1]) << "monomers " << k << " and " << k + 1;
}

TEST(Render2D, AClusterKeepsItsColourWhenOthersMergeAndLabelsShift) {
  Picture<2> p;
  p.particles.box = {60.0, Boundary::walls};
  for (int k = 0; k < 30; ++k) p.add(Vec<2>(2.0 + 3.0 * (k % 10), 2.0 + 3.0 * (k / 10)), 0.5, k);
  p.add(Vec<2>(50.0, 50.0), 0.5, 30);  // far from everything
  for (int k = 0; k < 5; ++k) p.add(Vec<2>(40.0 + k, 40.0), 0.5, 31);  // the largest
  const std::uint8_t before = cluster_colours(p.frame, p.particles, 31)[30];
  // Spheres 3 and 4 merge: labels after them shift down by one (order of first sphere).
  for (std::int32_t& l : p.frame.cluster)
    if (l >= 4) --l;
  EXPECT_EQ(cluster_colours(p.frame, p.particles, 30)[30], before);
}

// View straight down the z axis: the picture's x and y are the world's.
const View3 kTopView{Vec<3>(0.0, 0.0, 1.0), Vec<3>(-0.45, 0.6, 0.75)};

struct Panel3 {
  Layout l = make_layout(kWidth);
  double k;  // pixels per unit, box of side L framed with the renderer's 4 % margin
  explicit Panel3(double length) : k(l.side / (1.04 * length)) {}
  double x(double wx, double length) const { return l.margin + l.side / 2 + (wx - length / 2) * k; }
  double y(double wy, double length) const { return l.margin + l.side / 2 - (wy - length / 2) * k; }
};

TEST(Render3D, ASphereIsShadedFromTheLightAndDrawnToScale) {
  Picture<3> p;
  p.particles.box = {10.0, Boundary::walls};
  p.add(Vec<3>(5.0, 5.0, 5.0), 1.0, 0);
  const Raster image(render_image(make_scene(p.frame, p.particles), {kWidth, kTopView}));
  const Panel3 m(10.0);
  const double cx = m.x(5.0, 10.0), cy = m.y(5.0, 10.0), r = m.k;
  int covered = 0;
  for (int y = static_cast<int>(cy - 1.5 * r); y <= cy + 1.5 * r; ++y)
    for (int x = static_cast<int>(cx - 1.5 * r); x <= cx + 1.5 * r; ++x) covered += !image.white(x, y);
  EXPECT_NEAR(covered, std::numbers::pi * r * r, 0.03 * std::numbers::pi * r * r);
  // The light comes from the upper left: that side is brighter than the lower right.
  const Pixel lit = image.at(static_cast<int>(cx - 0.4 * r), static_cast<int>(cy - 0.4 * r));
  const Pixel shaded = image.at(static_cast<int>(cx + 0.6 * r), static_cast<int>(cy + 0.6 * r));
  EXPECT_GT(lit.r, shaded.r + 60);
}

TEST(Render3D, TheNearerSphereHidesTheFartherOne) {
  for (const bool red_in_front : {true, false}) {
    Picture<3> p;
    p.particles.box = {10.0, Boundary::walls};
    // Cluster 0 (two spheres) is the largest, so red; cluster 1 is a palette colour.
    p.add(Vec<3>(5.0, 5.0, red_in_front ? 7.0 : 3.0), 1.0, 0);
    p.add(Vec<3>(1.5, 1.5, 1.5), 1.0, 0);
    p.add(Vec<3>(5.0, 5.0, red_in_front ? 3.0 : 7.0), 1.0, 1);
    const Raster image(render_image(make_scene(p.frame, p.particles), {kWidth, kTopView}));
    const Panel3 m(10.0);
    const Pixel centre = image.at(static_cast<int>(m.x(5.0, 10.0)), static_cast<int>(m.y(5.0, 10.0)));
    const bool looks_red = centre.r > 2 * centre.g && centre.r > 2 * centre.b;
    EXPECT_EQ(looks_red, red_in_front) << centre.r << "," << centre.g << "," << centre.b;
  }
}

TEST(Render3D, SpheresCrossingAPeriodicFaceAreCutAtTheFaceAndShownOnTheOtherSide) {
  Picture<3> p;
  p.particles.box = {10.0, Boundary::periodic};
  p.add(Vec<3>(0.3, 5.0, 5.0), 1.0, 0);
  p.frame.image.push_back(ballagg::Image<3>::Zero());
  const Raster image(render_image(make_scene(p.frame, p.particles), {kWidth, kTopView}));
  const Panel3 m(10.0);
  const int row = static_cast<int>(m.y(5.0, 10.0));
  EXPECT_TRUE(image.white(static_cast<int>(m.x(-0.2, 10.0)), row)) << "the sphere pokes out of the box";
  EXPECT_FALSE(image.white(static_cast<int>(m.x(0.6, 10.0)), row));
  EXPECT_FALSE(image.white(static_cast<int>(m.x(9.6, 10.0)), row)) << "no image on the other side";
  EXPECT_TRUE(image.white(static_cast<int>(m.x(10.2, 10.0)), row));
}

TEST(RenderPov, TheSceneHasEverySphereOfTheAggregateAndPovRayRendersIt) {
  Picture<3> p;
  p.particles.box = {20.0, Boundary::walls};
  for (int k = 0; k < 7; ++k) p.add(Vec<3>(5.0 + k, 5.0 + 0.5 * k, 5.0), 0.5, 0);
  p.add(Vec<3>(15.0, 15.0, 15.0), 0.5, 1);
  const std::string text = pov_scene_text(make_scene(p.frame, p.particles, 1), View3{});
  std::size_t spheres = 0;
  for (std::size_t at = text.find("  sphere {"); at != std::string::npos; at = text.find("  sphere {", at + 1)) ++spheres;
  EXPECT_EQ(spheres, 7u);
  EXPECT_CONTAINS(text, "camera {");
  if (std::system("command -v povray >/dev/null 2>&1") != 0) GTEST_SKIP() << "povray is not installed";
  const TempDir dir;
  testing::write(dir / "a.pov", text);
  const std::string command = "cd " + testing::quoted(dir.path().string()) +
                              " && povray +W64 +H64 -D -V +Oa.png a.pov >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const Raster image = Raster::from_png((dir / "a.png").string());
  ASSERT_TRUE(image.ok());
  int coloured = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) coloured += !image.white(x, y);
  EXPECT_GT(coloured, 64 * 64 / 20);
  EXPECT_LT(coloured, 64 * 64);
}

// ---------------------------------------------------------------------------------------
// The command line

class RenderCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = new TempDir("ballagg-test-render-");
    const testing::Outcome two = testing::run_ballagg(
        {"run", "-q", "--out", (scratch_->path() / "run2").string(), "--set", "system.n=100", "--set",
         "system.boundary=periodic", "--set", "output.snapshot_every=3"},
        scratch_->path());
    ASSERT_EQ(two.status, 0) << two.err;
    const testing::Outcome three = testing::run_ballagg(
        {"run", "-q", "--out", (scratch_->path() / "run3").string(), "--set", "system.dimension=3", "--set",
         "system.n=200", "--set", "system.boundary=periodic", "--set", "system.volume_fraction=0.1", "--set",
         "stop.clusters=5", "--set", "output.snapshot_every=2"},
        scratch_->path());
    ASSERT_EQ(three.status, 0) << three.err;
  }
  static void TearDownTestSuite() { delete scratch_; }

  static fs::path run2() { return scratch_->path() / "run2"; }
  static fs::path run3() { return scratch_->path() / "run3"; }
  fs::path out(const std::string& name) const { return dir_.path() / name; }
  testing::Outcome render(std::vector<std::string> args) const {
    args.insert(args.begin(), "render");
    return testing::run_ballagg(args, dir_.path());
  }
  // Exit status 2, one line on stderr naming the problem, nothing written.
  void expect_bad_input(const std::vector<std::string>& args, const std::string& needle) const {
    const testing::Outcome o = render(args);
    EXPECT_EQ(o.status, 2) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    EXPECT_EQ(o.err.rfind("ballagg: error: ", 0), 0u) << o.err;
    EXPECT_CONTAINS(o.err, needle);
    EXPECT_EQ(o.out, "");
    EXPECT_TRUE(fs::is_empty(dir_.path())) << "something was written";
  }

  static TempDir* scratch_;
  const TempDir dir_{"ballagg-test-render-out-"};
};

TempDir* RenderCli::scratch_ = nullptr;

TEST_F(RenderCli, DefaultPictureIsFinalPngInTheRunDirectory) {
  const testing::Outcome o = render({run2().string()});
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_CONTAINS(o.out, "final.png");
  const Raster image = Raster::from_png((run2() / "final.png").string());
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.width(), 1200);
  fs::remove(run2() / "final.png");
}

TEST_F(RenderCli, AFrameAsPngAndSvg) {
  const testing::Outcome o = render({run2().string(), "--frame", "1", "--png", out("f.png").string(), "--svg",
                                     out("f.svg").string(), "--width", "300"});
  ASSERT_EQ(o.status, 0) << o.err;
  const Raster image = Raster::from_png(out("f.png").string());
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.width(), 300);
  const std::string svg = testing::slurp(out("f.svg"));
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_CONTAINS(svg, "<svg");
  for (const auto& e : fs::directory_iterator(dir_.path())) EXPECT_NE(e.path().filename().string().front(), '.');
}

TEST_F(RenderCli, VideoHasOneFramePerSnapshot) {
  if (std::system("command -v ffprobe >/dev/null 2>&1") != 0) GTEST_SKIP() << "ffmpeg is not installed";
  const testing::Outcome o = render({run2().string(), "--video", out("v.mp4").string(), "--width", "160", "--fps", "5"});
  ASSERT_EQ(o.status, 0) << o.err;
  const int frames = H5mdReader<2>((run2() / "trajectory.h5md").string()).frames();
  const std::string command = "ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames,width "
                              "-of csv=p=0 " + testing::quoted(out("v.mp4").string()) + " > " +
                              testing::quoted(out("probe").string());
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(testing::slurp(out("probe")), fmt::format("160,{}\n", frames));
}

// A video that outgrows the disk is reported like every output file (docs/hardening.md):
// status 2, one line naming it and the reason, and no file left, not even a temporary.
// ffmpeg's write fails first; the reason is the errno of our own write where it failed.
TEST_F(RenderCli, VideoBeyondAFileSizeLimitIsOneLineNamingItAndLeavesNoPartialFile) {
  if (std::system("command -v ffprobe >/dev/null 2>&1") != 0) GTEST_SKIP() << "ffmpeg is not installed";
  const testing::Outcome whole = render({run2().string(), "--video", out("v.mp4").string()});
  ASSERT_EQ(whole.status, 0) << whole.err;
  const std::uintmax_t size = fs::file_size(out("v.mp4"));
  fs::remove(out("v.mp4"));
  // 16 KiB: the first frames do not fit. Just under the whole video: only the end does
  // not, which ffmpeg 5.1 (without -xerror) reported with status 0, leaving it truncated.
  // With SIGXFSZ ignored by the shell and without: ballagg ignores it itself, and ffmpeg
  // inherits that.
  for (const std::uintmax_t kib : {std::uintmax_t{16}, size / 1024})
    for (const std::string trap : {"trap \"\" XFSZ; ", ""}) {
      SCOPED_TRACE(fmt::format("{}ulimit -f {} ({} bytes whole)", trap, kib, size));
      const std::string limited = fmt::format("bash -c '{}ulimit -f {}; exec \"$0\" \"$@\"'", trap, kib);
      const testing::Outcome o =
          testing::run_ballagg({"render", run2().string(), "--video", out("v.mp4").string()}, dir_.path(), limited);
      EXPECT_EQ(o.status, 2) << o.err;
      EXPECT_EQ(o.err, "ballagg: error: " + out("v.mp4").string() + ": cannot write: File too large\n");
      EXPECT_TRUE(fs::is_empty(dir_.path())) << "something was left";
    }
}

TEST_F(RenderCli, VideoOnAFullDiskIsOneLineNamingItAndLeavesNoPartialFile) {
  if (std::system("command -v ffprobe >/dev/null 2>&1") != 0) GTEST_SKIP() << "ffmpeg is not installed";
  // A 16 KiB tmpfs in a mount namespace of the command's own, as in test_cli's
  // NoSpaceLeftOnATinyFilesystemIsOneLineAndLeavesNoPartialFile.
  const fs::path disk = out("disk"), video = disk / "v.mp4", listing = out("listing");
  fs::create_directory(disk);
  const std::string inside = "mount -t tmpfs -o size=16k tmpfs " + testing::quoted(disk.string()) +
                             " || exit 77; \"$0\" \"$@\"; s=$?; ls -A " + testing::quoted(disk.string()) + " > " +
                             testing::quoted(listing.string()) + "; exit $s";
  const testing::Outcome o = testing::run_ballagg({"render", run2().string(), "--video", video.string()}, dir_.path(),
                                                  "unshare --user --map-root-user --mount sh -c " + testing::quoted(inside));
  if (o.status == 77 || !fs::exists(listing)) GTEST_SKIP() << "cannot mount a tmpfs in a user namespace here";
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_EQ(o.err, "ballagg: error: " + video.string() + ": cannot write: No space left on device\n");
  EXPECT_EQ(testing::slurp(listing), "") << "left on the full disk";
}

TEST_F(RenderCli, AnFfmpegFailureThatIsNotTheDiskIsStatusOneWithItsMessage) {
  // A stand-in ffmpeg that reads every frame, reports an error and exits with status 0
  // (as ffmpeg 5.1 does when it cannot write the trailer, unless given -xerror): an
  // error message is a failure whatever the status.
  const TempDir bin("ballagg-test-fake-ffmpeg-");
  const fs::path fake = bin.path() / "ffmpeg";
  testing::write(fake, "#!/bin/sh\ncat > /dev/null\necho 'Something else went wrong' >&2\nexit 0\n");
  fs::permissions(fake, fs::perms::owner_all);
  const testing::Outcome o = testing::run_ballagg({"render", run2().string(), "--video", out("v.mp4").string()},
                                                  dir_.path(), "env PATH=" + testing::quoted(bin.path().string()) + ":\"$PATH\"");
  EXPECT_EQ(o.status, 1) << o.err;
  EXPECT_EQ(o.err, "ballagg: failed: " + out("v.mp4").string() + ": ffmpeg failed: Something else went wrong\n");
  EXPECT_TRUE(fs::is_empty(dir_.path())) << "something was left";
}

// The frames' progress on stderr (a plain line in a pipe, the last once the video is
// written), and nothing there with --quiet. A stand-in ffmpeg that copies the frames into
// its output file: the progress is ours, not ffmpeg's, so the test needs no ffmpeg.
TEST_F(RenderCli, VideoProgressCountsTheFramesAndQuietSilencesIt) {
  const TempDir bin("ballagg-test-fake-ffmpeg-");
  const fs::path fake = bin.path() / "ffmpeg";
  testing::write(fake, "#!/bin/sh\nfor last; do :; done\ncat > \"$last\"\n");
  fs::permissions(fake, fs::perms::owner_all);
  const std::string path = "env PATH=" + testing::quoted(bin.path().string()) + ":\"$PATH\"";
  const int frames = H5mdReader<2>((run2() / "trajectory.h5md").string()).frames();
  ASSERT_GT(frames, 1);
  const testing::Outcome o = testing::run_ballagg(
      {"render", run2().string(), "--video", out("v.mp4").string(), "--width", "160"}, dir_.path(), path);
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(o.out, fmt::format("wrote {} ({} frames)\n", out("v.mp4").string(), frames));
  // Not a terminal: plain lines, the last one when the video is complete.
  const std::regex last(fmt::format(R"((^|\n)100%  frames {} / {}  [0-9]+\.[0-9] s\n$)", frames, frames));
  EXPECT_TRUE(std::regex_search(o.err, last)) << o.err;
  EXPECT_EQ(o.err.find('\r'), std::string::npos) << "a bar redrawn in place, not on a terminal";
  fs::remove(out("v.mp4"));
  const testing::Outcome quiet = testing::run_ballagg(
      {"render", run2().string(), "--video", out("v.mp4").string(), "--width", "160", "-q"}, dir_.path(), path);
  ASSERT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_EQ(quiet.err, "");
  EXPECT_EQ(quiet.out, fmt::format("wrote {} ({} frames)\n", out("v.mp4").string(), frames));
}

TEST_F(RenderCli, ThreeDPictureAggregateAndPovRayScene) {
  const testing::Outcome o = render({run3().string(), "--png", out("box.png").string(), "--width", "200"});
  ASSERT_EQ(o.status, 0) << o.err;
  const testing::Outcome a = render({run3().string(), "--aggregate", "2", "--png", out("a.png").string(), "--pov",
                                     out("a.pov").string(), "--width", "200", "--view", "0,1,1", "--light", "1,1,1"});
  ASSERT_EQ(a.status, 0) << a.err;
  EXPECT_TRUE(Raster::from_png(out("box.png").string()).ok());
  EXPECT_TRUE(Raster::from_png(out("a.png").string()).ok());
  EXPECT_CONTAINS(testing::slurp(out("a.pov")), "aggregate 2 by size");
}

TEST_F(RenderCli, BadArgumentsAreOneLineErrors) {
  const std::string r2 = run2().string(), r3 = run3().string();
  expect_bad_input({(dir_.path() / "nothing").string()}, "not a run directory");
  expect_bad_input({r2, "--frame", "1000"}, "--frame 1000: ");
  expect_bad_input({r2, "--frame", "-1"}, "--frame -1: must be 0 or more");
  expect_bad_input({r2, "--png", (dir_.path() / "no/such/dir/x.png").string()}, "cannot write");
  expect_bad_input({r2, "--png", out("x.jpg").string()}, "must end in .png");
  expect_bad_input({r2, "--video", out("x.avi").string()}, "must end in .mp4");
  expect_bad_input({r2, "--pov", out("x.pov").string()}, "POV-Ray scenes are for 3D runs");
  expect_bad_input({r2, "--view", "1,0,0"}, "--view: only for 3D runs");
  expect_bad_input({r2, "--width", "20"}, "--width 20: must be from 64");
  expect_bad_input({r3, "--width", "5000"}, "--width 5000: 3D pictures must be from 64 to 4096 pixels");
  expect_bad_input({r2, "--fps", "0"}, "--fps 0");
  expect_bad_input({r2, "--frame", "1", "--video", out("v.mp4").string()}, "--frame and --video");
  expect_bad_input({r3, "--aggregate", "99", "--png", out("x.png").string()}, "--aggregate 99: there are only");
  expect_bad_input({r3, "--view", "0,0,0"}, "must be a non-zero direction");
  expect_bad_input({r2, "--bogus"}, "--bogus");
}

TEST_F(RenderCli, ARunWithoutTrajectoryHasNoFrames) {
  const TempDir scratch;
  ASSERT_EQ(testing::run_ballagg({"run", "-q", "--out", (scratch / "r").string(), "--set", "system.n=16"}, scratch.path())
                .status,
            0);
  expect_bad_input({(scratch / "r").string(), "--frame", "0"}, "output.snapshot_every");
}

// A rigid-body run (rotating aggregates, Richardson 1995): its last trajectory frame (in
// double precision) is final.csv to the bit (member spheres in the space frame, same
// cluster ids), the pictures render, and the POV-Ray scene of its largest aggregate holds
// every sphere of it in one piece: each touches another at exactly a contact distance.
TEST(RenderRigidBody, TrajectoryPicturesAndOneAggregateForPovRay) {
  const TempDir dir;
  const fs::path run = dir / "run";
  const testing::Outcome o = testing::run_ballagg(
      {"run", "-q", "--out", run.string(), "--set", "engine.kind=\"rigid-body\"", "--set", "system.dimension=3", "--set",
       "system.n=300", "--set", "system.boundary=periodic", "--set", "system.volume_fraction=0.1", "--set",
       "initial.velocities=\"gaussian\"", "--set", "stop.clusters=20", "--set", "output.snapshot_every=0.5", "--set",
       "output.snapshot_precision=double"},
      dir.path());
  ASSERT_EQ(o.status, 0) << o.err;
  const H5mdReader<3> trajectory((run / "trajectory.h5md").string());
  const Frame<3> last = trajectory.frame(trajectory.frames() - 1);
  const SphereTable<3> final_state = read_state_csv<3>((run / "final.csv").string());
  ASSERT_EQ(last.size(), static_cast<int>(final_state.position.size()));
  for (int i = 0; i < last.size(); ++i) {
    ASSERT_EQ(last.position[i], final_state.position[i]) << "sphere " << i;
    ASSERT_EQ(last.cluster[i], final_state.cluster[i]) << "sphere " << i;
  }
  const std::string frame = std::to_string(trajectory.frames() / 2);
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--frame", frame, "--png", (dir / "mid.png").string()},
        std::vector<std::string>{"--aggregate", "1", "--png", (dir / "a.png").string(), "--pov", (dir / "a.pov").string()}}) {
    std::vector<std::string> command{"render", run.string()};
    command.insert(command.end(), args.begin(), args.end());
    const testing::Outcome r = testing::run_ballagg(command, dir.path());
    ASSERT_EQ(r.status, 0) << r.err;
  }
  EXPECT_TRUE(Raster::from_png((dir / "mid.png").string()).ok());
  EXPECT_TRUE(Raster::from_png((dir / "a.png").string()).ok());

  std::vector<Vec<3>> centre;
  std::vector<double> radius;
  const std::string pov = testing::slurp(dir / "a.pov");
  for (std::size_t at = pov.find("  sphere { <"); at != std::string::npos; at = pov.find("  sphere { <", at + 1)) {
    double x, z, y, r;  // the scene's frame is y-up
    ASSERT_EQ(std::sscanf(pov.c_str() + at, "  sphere { <%lf, %lf, %lf>, %lf", &x, &z, &y, &r), 4);
    centre.emplace_back(x, y, z);
    radius.push_back(r);
  }
  int largest = 0;
  for (std::int64_t c : final_state.cluster)
    largest = std::max(largest, static_cast<int>(std::count(final_state.cluster.begin(), final_state.cluster.end(), c)));
  ASSERT_EQ(static_cast<int>(centre.size()), largest);
  ASSERT_GT(largest, 5);
  for (std::size_t i = 0; i < centre.size(); ++i) {
    double nearest = 1e300;  // gap over contact distance
    for (std::size_t j = 0; j < centre.size(); ++j)
      if (j != i) nearest = std::min(nearest, (centre[i] - centre[j]).norm() / (radius[i] + radius[j]) - 1.0);
    EXPECT_NEAR(nearest, 0.0, 1e-9) << "sphere " << i << " of the aggregate";
  }
}

}  // namespace
}  // namespace ballagg
