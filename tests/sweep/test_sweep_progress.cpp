// The lines `ballagg sweep` prints while it runs: the parameters of a point, the estimate of
// the time left (from each run's own time, so the same whatever the runs at once), and
// --quiet.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "ballagg/sweep/sweep_progress.hpp"
#include "ballagg/sweep/sweep_spec.hpp"

namespace ballagg {
namespace {

const char* kTwoVariants = R"([grid]
system.n = [16, 25]
[[variants]]
label = "ts rigid"
engine.kind = "ts"
[[variants]]
engine.kind = "ed"
)";

// The text a SweepProgress writes, through a memory stream.
class CapturedOutput {
 public:
  CapturedOutput() : file_(open_memstream(&data_, &size_)) {}
  ~CapturedOutput() {
    std::fclose(file_);
    std::free(data_);
  }
  std::FILE* file() { return file_; }
  std::string text() {
    std::fflush(file_);
    return std::string(data_, size_);
  }

 private:
  char* data_ = nullptr;
  std::size_t size_ = 0;
  std::FILE* file_;
};

TEST(SweepProgress, PointParametersAreTheVariantAndTheGridValues) {
  const SweepSpec spec = parse_sweep_text(kTwoVariants, "s.toml");
  const auto points = sweep_points(spec);
  ASSERT_EQ(points.size(), 4u);
  EXPECT_EQ(point_parameters(spec, points[1]), "ts rigid: system.n = 25");
  EXPECT_EQ(point_parameters(spec, points[2]), "engine.kind=\"ed\": system.n = 16");
  // Without [[variants]] the one empty variant is not named.
  const SweepSpec plain = parse_sweep_text("[grid]\nsystem.n = [16]\ninitial.velocities = [\"gaussian\"]\n", "s.toml");
  EXPECT_FALSE(has_variants(plain));
  EXPECT_EQ(point_parameters(plain, sweep_points(plain)[0]), "system.n = 16, initial.velocities = \"gaussian\"");
  const SweepSpec no_grid = parse_sweep_text("[[variants]]\nlabel = \"a\"\nengine.kind = \"ed\"\n", "s.toml");
  EXPECT_EQ(point_parameters(no_grid, sweep_points(no_grid)[0]), "a");
  const SweepSpec nothing = parse_sweep_text("[sweep]\nrealizations = 2\n", "s.toml");
  EXPECT_EQ(point_parameters(nothing, sweep_points(nothing)[0]), "");
}

TEST(SweepProgress, TimeLeftIsTheMeanRunTimesTheRunsLeftOverTheRunsAtOnce) {
  EXPECT_DOUBLE_EQ(estimated_seconds_left(2.0, 6, 1), 12.0);
  EXPECT_DOUBLE_EQ(estimated_seconds_left(2.0, 6, 3), 4.0);
  // Fewer runs left than jobs: they run side by side, each in its own time.
  EXPECT_DOUBLE_EQ(estimated_seconds_left(2.0, 1, 4), 2.0);
  EXPECT_DOUBLE_EQ(estimated_seconds_left(2.0, 0, 4), 0.0);
}

TEST(SweepProgress, DurationsAreRoundedToAUnitReadAtAGlance) {
  EXPECT_EQ(approximate_duration(0.2), "under 1 s");
  EXPECT_EQ(approximate_duration(44.6), "about 45 s");
  EXPECT_EQ(approximate_duration(600.0), "about 10 min");
  EXPECT_EQ(approximate_duration(3.0 * 3600.0), "about 3.0 h");
}

TEST(SweepProgress, OneLinePerRunWithItsRankParametersAndEstimate) {
  const SweepSpec spec = parse_sweep_text(kTwoVariants, "s.toml");
  const auto points = sweep_points(spec);
  const auto runs = sweep_runs(spec, points);
  CapturedOutput out;
  SweepProgress progress(spec, out.file(), false, 3, 2, "");
  progress.start(1);
  progress.done(runs[0], points[0], 10.0);
  progress.done(runs[3], points[3], 30.0);  // mean 20 s, one run left: 20 s
  progress.done(runs[1], points[1], 5.0);
  EXPECT_EQ(out.text(),
            "sweep: 3 runs to do, 1 finished already, 2 at once\n"
            "sweep: [1/3] about 10 s left (estimate); runs/p000-r00 (ts rigid: system.n = 16) done\n"
            "sweep: [2/3] about 20 s left (estimate); runs/p003-r00 (engine.kind=\"ed\": system.n = 25) done\n"
            "sweep: [3/3] runs/p001-r00 (ts rigid: system.n = 25) done\n");
}

TEST(SweepProgress, QuietPrintsNothing) {
  const SweepSpec spec = parse_sweep_text(kTwoVariants, "s.toml");
  const auto points = sweep_points(spec);
  const auto runs = sweep_runs(spec, points);
  CapturedOutput out;
  SweepProgress progress(spec, out.file(), true, 2, 1, "");
  progress.start(0);
  progress.done(runs[0], points[0], 1.0);
  progress.done(runs[1], points[1], 1.0);
  EXPECT_EQ(out.text(), "");
}

}  // namespace
}  // namespace ballagg
