// `ballagg plot`: the lines of a sweep are its variants, with their labels; a panel is
// drawn only with data; the formats, resolution, panel size and style options; the figures
// of single runs (event-driven and rigid-body); the script a user copies and edits; bad
// options as one line. Figures are read back as files: SVG text (legend entries, axes
// groups), PNG headers (pixel size), magic bytes.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using ballagg::testing::run_ballagg;
using ballagg::testing::slurp;
using ballagg::testing::TempDir;

namespace {

// Two event-driven variants that differ in a key other than the method and dt, 100 and 144
// discs, two realizations each (milliseconds a run). Fewer discs leave a box too small for
// three box-counting levels, and D_f is then withheld (docs/analysis.md).
const char* kTwoVariants = R"([sweep]
realizations = 2
seed_base = 40
[grid]
system.n = [100, 144]
system.volume_fraction = [0.2]
[[variants]]
label = "ed-fixed"
initial.velocities = "fixed-speed"
[[variants]]
label = "ed-gauss"
initial.velocities = "gaussian"
)";

// A time-stepping variant with its own label, to compare with the sweep above.
const char* kTimeStepping = R"([sweep]
realizations = 2
seed_base = 40
[grid]
system.n = [100, 144]
system.volume_fraction = [0.2]
[[variants]]
label = "ts-rigid"
engine.kind = "ts"
)";

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// The panels of an SVG figure: each draws an x and a y axis (the slot of a legend beside
// the panels draws none).
std::size_t panels(const std::string& svg) { return count(svg, "<g id=\"matplotlib.axis_") / 2; }

// Width and height of a PNG file from its IHDR chunk (bytes 16 to 23, big-endian).
std::pair<std::uint32_t, std::uint32_t> png_size(const fs::path& png) {
  const std::string b = slurp(png);
  if (b.size() < 24 || b.compare(1, 3, "PNG") != 0) return {0, 0};
  auto word = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 4; ++k) v = v << 8 | static_cast<unsigned char>(b[at + k]);
    return v;
  };
  return {word(16), word(20)};
}

// The sweeps and runs every test plots, made once.
class Plot : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const TempDir& d = *dir_;
    for (const auto& [name, text] : {std::pair{"variants", kTwoVariants}, std::pair{"ts", kTimeStepping}}) {
      const fs::path file = d.write(fmt::format("{}.toml", name), text);
      const auto o = run_ballagg({"sweep", "-q", file.string(), "--out", (d / name).string(), "--jobs", "2"}, d.path());
      ASSERT_EQ(o.status, 0) << o.err;
    }
    for (const auto& [name, engine] : {std::pair{"ed", "ed"}, std::pair{"raw", "ed"}, std::pair{"rigid", "rigid-body"}}) {
      const auto o = run_ballagg({"run", "-q", "--out", (d / name).string(), "--set", "system.n=60", "--set",
                                  fmt::format("engine.kind={}", engine)}, d.path());
      ASSERT_EQ(o.status, 0) << o.err;
    }
    ASSERT_EQ(run_ballagg({"analyze", (d / "ed").string()}, d.path()).status, 0);
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path at(const std::string& name) { return *dir_ / name; }
  // The figures of the analysed event-driven run in one of the ways several tests look at,
  // drawn once: "png" (the defaults), "pdf", "svg" (with a style file), "small" (--dpi, --size).
  static fs::path drawn(const std::string& how) {
    const fs::path out = at("ed_" + how);
    if (fs::exists(out)) return out;
    std::vector<std::string> args = {at("ed").string(), "--out", out.string()};
    if (how == "pdf") args.insert(args.end(), {"--format", "pdf"});
    if (how == "svg")
      args.insert(args.end(), {"--format", "svg", "--style",
                               dir_->write("mine.mplstyle", "axes.facecolor: 1a2b3c\n").string()});
    if (how == "small") args.insert(args.end(), {"--dpi", "50", "--size", "2x1.5"});
    const auto o = plot(args);
    EXPECT_EQ(o.status, 0) << o.err;
    return out;
  }
  static ballagg::testing::Outcome plot(std::vector<std::string> args) {
    args.insert(args.begin(), "plot");
    return run_ballagg(args, dir_->path());
  }
  static TempDir* dir_;
};

TempDir* Plot::dir_ = nullptr;

TEST_F(Plot, VariantsAreLinesWithTheirLabelsAndNoPanelIsEmpty) {
  const fs::path out = at("variants_svg");
  const auto o = plot({at("variants").string(), "--format", "svg", "--out", out.string()});
  ASSERT_EQ(o.status, 0) << o.err;
  for (const char* figure : {"contacts.svg", "aspect_ratio.svg", "fractal_dimension.svg", "pair_distribution.svg"}) {
    SCOPED_TRACE(figure);
    const std::string svg = slurp(out / figure);
    // Two lines, each named by its variant: not one line "ed" through both.
    EXPECT_NE(svg.find(">ed-fixed</text>"), std::string::npos);
    EXPECT_NE(svg.find(">ed-gauss</text>"), std::string::npos);
    EXPECT_EQ(svg.find(">ed</text>"), std::string::npos);
    EXPECT_EQ(svg.find("dt="), std::string::npos);
  }
  // No time stepping in the sweep: D_f against N alone, no empty TS-vs-ED panel.
  EXPECT_EQ(panels(slurp(out / "fractal_dimension.svg")), 1u);
  // P(r) with its error band; D_f with its error in the legend.
  EXPECT_GE(count(slurp(out / "pair_distribution.svg"), "<g id=\"PolyCollection_"), 2u);
  const std::string boxes = slurp(out / "box_counting.svg");
  EXPECT_NE(boxes.find("<!-- ed-fixed: $D_f$ = "), std::string::npos);
  EXPECT_NE(boxes.find(" ± "), std::string::npos);
  EXPECT_NE(boxes.find("box size $\\varepsilon/R$"), std::string::npos);
}

TEST_F(Plot, TimeSteppingAgainstEventDrivenGetsItsPanelAndKeepsItsLabel) {
  const fs::path out = at("both_svg");
  const auto o = plot({at("variants").string(), at("ts").string(), "--format", "svg", "--out", out.string()});
  ASSERT_EQ(o.status, 0) << o.err;
  const std::string svg = slurp(out / "fractal_dimension.svg");
  EXPECT_EQ(panels(svg), 2u);
  EXPECT_NE(svg.find(">ts-rigid</text>"), std::string::npos);
  EXPECT_EQ(svg.find("dt="), std::string::npos);  // "ts-rigid", not "ts-rigid dt=0.01"
  // Two event-driven lines: the TS line against each, named.
  EXPECT_NE(svg.find(">ts-rigid vs ed-fixed</text>"), std::string::npos);
  EXPECT_NE(svg.find(">ts-rigid vs ed-gauss</text>"), std::string::npos);
}

TEST_F(Plot, EachFormatWritesItsKindOfFile) {
  for (const auto& [format, magic] : {std::pair{"png", std::string("\x89PNG\r\n", 6)}, std::pair{"pdf", std::string("%PDF-")},
                                      std::pair{"svg", std::string("<?xml")}}) {
    SCOPED_TRACE(format);
    const fs::path out = drawn(std::string(format) == "png" ? "small" : format);  // a small PNG draws faster
    for (const char* name : {"timeseries", "pair_distribution", "box_counting", "mass_radius", "mass_spectrum"}) {
      const fs::path f = out / fmt::format("{}.{}", name, format);
      ASSERT_TRUE(fs::exists(f)) << f;
      EXPECT_EQ(slurp(f).substr(0, magic.size()), magic) << f;
    }
    EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator{}), 5) << "no temporary file left";
  }
}

TEST_F(Plot, DpiAndSizeSetThePixelsExactly) {
  // Default: 3.4 x 2.6 in per panel at 300 dpi; the time series is 2 x 2 panels.
  EXPECT_EQ(png_size(drawn("png") / "mass_spectrum.png"), std::pair(1020u, 780u));
  EXPECT_EQ(png_size(drawn("png") / "timeseries.png"), std::pair(2040u, 1560u));
  EXPECT_EQ(png_size(drawn("small") / "mass_spectrum.png"), std::pair(100u, 75u));
  EXPECT_EQ(png_size(drawn("small") / "timeseries.png"), std::pair(200u, 150u));
}

TEST_F(Plot, StyleFileIsAppliedOnTopOfTheDefaults) {
  // The SVG is drawn with a style file setting the panels' colour.
  const std::string svg = slurp(drawn("svg") / "mass_spectrum.svg");
  EXPECT_NE(svg.find("fill: #1a2b3c"), std::string::npos);
  // The defaults stay where the style says nothing: 7 pt tick labels.
  EXPECT_NE(svg.find("font: 7px"), std::string::npos);
}

TEST_F(Plot, RunDirectoriesOfBothKindsOfEngine) {
  const fs::path rigid = at("run_rigid");
  // Clusters, largest cluster, kinetic energy, momentum.
  EXPECT_EQ(panels(slurp(drawn("svg") / "timeseries.svg")), 4u);
  // A rigid-body run (analysed by the run itself) adds the velocity dispersion and the
  // rotational energy.
  const auto r = plot({at("rigid").string(), "--format", "svg", "--out", rigid.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string series = slurp(rigid / "timeseries.svg");
  EXPECT_EQ(panels(series), 6u);
  EXPECT_NE(series.find("velocity dispersion"), std::string::npos);
  EXPECT_NE(series.find("rotational energy"), std::string::npos);
  for (const char* f : {"pair_distribution.svg", "box_counting.svg", "mass_radius.svg", "mass_spectrum.svg"})
    EXPECT_TRUE(fs::exists(rigid / f)) << f;
  // Not analysed: the time series, and one line saying how to get the rest.
  const auto raw = plot({at("raw").string()});
  ASSERT_EQ(raw.status, 0) << raw.err;
  EXPECT_TRUE(fs::exists(at("raw") / "figures" / "timeseries.png"));
  EXPECT_FALSE(fs::exists(at("raw") / "figures" / "box_counting.png"));
  EXPECT_NE(raw.out.find(fmt::format("run `ballagg analyze {}` first", at("raw").string())), std::string::npos) << raw.out;
}

TEST_F(Plot, FramesAndKineticsOfARunAreDrawnAgainstTime) {
  const fs::path run = at("framed"), out = at("framed_figures");
  ASSERT_EQ(run_ballagg({"run", "-q", "--out", run.string(), "--set", "system.n=100", "--set",
                         "output.snapshot_every=4"}, dir_->path()).status, 0);
  const auto a = run_ballagg({"analyze", run.string(), "--frames"}, dir_->path());
  ASSERT_EQ(a.status, 0) << a.err;
  const auto k = run_ballagg({"analyze", run.string(), "--kinetics"}, dir_->path());
  ASSERT_EQ(k.status, 0) << k.err;
  const auto o = plot({run.string(), "--format", "svg", "--out", out.string()});
  ASSERT_EQ(o.status, 0) << o.err;
  const std::string indicators = slurp(out / "frames_indicators.svg");
  EXPECT_EQ(panels(indicators), 4u);
  EXPECT_NE(indicators.find("all centres"), std::string::npos);
  // Four frames of the spectrum at most, named by their times.
  const std::string spectrum = slurp(out / "frames_mass_spectrum.svg");
  EXPECT_EQ(count(spectrum, "$t$ = "), 4u);
  EXPECT_TRUE(fs::exists(out / "frames_r_max.svg"));
  // n(t) and E(t) beside each other, and the collapse of the frames' size distributions.
  EXPECT_EQ(panels(slurp(out / "kinetics.svg")), 2u);
  EXPECT_TRUE(fs::exists(out / "kinetics_collapse.svg"));
  // A run without frame tables gets none of these figures.
  EXPECT_FALSE(fs::exists(drawn("svg") / "frames_indicators.svg"));
}

TEST_F(Plot, TheScriptIsAFileToCopyEditAndRun) {
  const auto printed = plot({"--print-script"});
  ASSERT_EQ(printed.status, 0) << printed.err;
  EXPECT_EQ(printed.out, slurp(fs::path(BALLAGG_SOURCE_DIR) / "scripts" / "ballagg_plot.py"));
  // An edited copy: its own figure file name.
  std::string edited = printed.out;
  const std::string from = "\"mass_spectrum\", \"mass_spectrum.csv\"";
  ASSERT_NE(edited.find(from), std::string::npos);
  edited.replace(edited.find(from), from.size(), "\"my_spectrum\", \"mass_spectrum.csv\"");
  const fs::path script = dir_->write("my_plot.py", edited);
  const fs::path out = at("edited");
  const auto o = plot({at("ed").string(), "--script", script.string(), "--out", out.string()});
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_TRUE(fs::exists(out / "my_spectrum.png"));
  EXPECT_FALSE(fs::exists(out / "mass_spectrum.png"));
}

TEST_F(Plot, BadOptionsAreOneLineAndWriteNothing) {
  const fs::path bad_style = dir_->write("bad.mplstyle", "axes.facecolr: 123456\n");
  const fs::path out = at("never");
  const std::string ed = at("ed").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{ed, "--format", "gif"}, "ballagg plot: error: --format gif: not a format (png, pdf, svg)\n"},
      {{ed, "--dpi", "5"}, "ballagg plot: error: --dpi 5: not an integer from 10 to 2400\n"},
      {{ed, "--size", "3x"}, "ballagg plot: error: --size 3x: not WIDTHxHEIGHT in inches, each from 0.5 to 50 (e.g. 3.4x2.6)\n"},
      {{ed, "--style", bad_style.string()},
       fmt::format("ballagg plot: error: --style {0}: Bad key axes.facecolr in file {0}, line 1 ('axes.facecolr: 123456')\n",
                   bad_style.string())},
      {{ed, at("variants").string()},
       fmt::format("ballagg plot: error: {}, {}: sweep and run directories mixed (plot sweeps together, or runs together)\n",
                   ed, at("variants").string())},
      {{ed, "--script", (*dir_ / "missing.py").string()},
       fmt::format("ballagg: error: --script {}: no such file (write the built-in one with: ballagg plot --print-script > FILE)\n",
                   (*dir_ / "missing.py").string())},
  };
  for (const auto& [args, message] : cases) {
    std::vector<std::string> all = args;
    all.insert(all.end(), {"--out", out.string()});
    SCOPED_TRACE(fmt::format("{}", fmt::join(all, " ")));
    const auto o = plot(all);
    EXPECT_EQ(o.status, 2);
    EXPECT_EQ(o.err, message);
    EXPECT_EQ(o.out, "");
    EXPECT_FALSE(fs::exists(out));
  }
}

}  // namespace
