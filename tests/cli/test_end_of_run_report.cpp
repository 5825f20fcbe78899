// What `run` and `analyze` print when they end (apps/ballagg/end_of_run_report.hpp), and
// the progress bar's choice of the stop criterion it follows.
#include <cstdio>
#include <limits>
#include <vector>
#include <string>

#include <gtest/gtest.h>

#include "ballagg/run/progress.hpp"
#include "cli_support.hpp"
#include "end_of_run_report.hpp"
#include "support.hpp"

using ballagg::testing::run_ballagg;
using ballagg::testing::TempDir;

TEST(EndOfRunReport, RunPrintsTheLoopAndTheFinalStateFromItsSummary) {
  TempDir dir;
  const auto r = run_ballagg({"run", "--set", "system.n=16", "--set", "output.xyz=false", "--out",
                              (dir / "r").string()}, dir.path());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("Loop: ed, 2D, 16 spheres; stopped by stop.clusters at t = "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" events in "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Final: 1 cluster (largest 16), kinetic energy "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("of the contact distance"), std::string::npos) << r.out;
  // The same words from the summary alone.
  const std::string report = ballagg::cli::run_report_of((dir / "r").string());
  EXPECT_NE(r.out.find(report), std::string::npos);
  const auto quiet = run_ballagg({"run", "-q", "--set", "system.n=16", "--set", "output.xyz=false", "--out",
                                  (dir / "q").string()}, dir.path());
  ASSERT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_EQ(quiet.out.find("Loop:"), std::string::npos) << quiet.out;
}

TEST(EndOfRunReport, TimeSteppingReportsStepsAndAStopByTime) {
  TempDir dir;
  const auto r = run_ballagg({"run", "--set", "engine.kind=ts", "--set", "system.n=25", "--set", "stop.time=2",
                              "--set", "output.xyz=false", "--out", (dir / "r").string()}, dir.path());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("Loop: ts, 2D, 25 spheres; stopped by stop.time at t = 2 after "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" steps in "), std::string::npos) << r.out;
}

TEST(EndOfRunReport, AnalyzePrintsTheHeadlineIndicatorsAndWithheldFits) {
  TempDir dir;
  ASSERT_EQ(run_ballagg({"run", "-q", "--set", "system.n=400", "--set", "output.xyz=false", "--out",
                         (dir / "r").string()}, dir.path()).status, 0);
  const auto a = run_ballagg({"analyze", (dir / "r").string()}, dir.path());
  ASSERT_EQ(a.status, 0) << a.err;
  EXPECT_NE(a.out.find("D_f = "), std::string::npos) << a.out;
  EXPECT_NE(a.out.find("(box counting over all spheres, "), std::string::npos) << a.out;
  EXPECT_NE(a.out.find("largest cluster: 400 spheres, A_r = "), std::string::npos) << a.out;
  const auto q = run_ballagg({"analyze", "-q", (dir / "r").string()}, dir.path());
  EXPECT_EQ(q.out.find("D_f"), std::string::npos) << q.out;
  // A fit the analysis withholds is printed as withheld, with its reason, never as a number.
  const nlohmann::json withheld = {
      {"all_spheres", {{"contacts", 0.5}, {"box_counting", {{"dimension", nullptr}, {"dimension_error", nullptr},
                                                            {"levels_fitted", 2}, {"flaw", "too_few_points"}}}}},
      {"largest_cluster", {{"size", 30}, {"aspect_ratio", 1.2}, {"radius_of_gyration", 3.0},
                           {"mass_radius_dimension", nullptr}, {"mass_radius_dimension_error", nullptr},
                           {"mass_radius_dimension_flaw", "hole_at_centre"}}}};
  const std::string h = ballagg::cli::analysis_headline(withheld);
  EXPECT_NE(h.find("D_f = withheld (too_few_points)"), std::string::npos) << h;
  EXPECT_NE(h.find("f_D = withheld (hole_at_centre)"), std::string::npos) << h;
}

// The progress line of a run that started with `start` clusters and stands at `now`.
std::string progress_line(const ballagg::State<2>& start, const ballagg::State<2>& now, const ballagg::StopCriteria& stop,
                          ballagg::StopReason reason) {
  std::FILE* out = std::tmpfile();
  ballagg::ProgressReporter<2> progress(out, false, stop);
  progress.on_start(start);
  ballagg::RunResult result;
  result.reason = reason;
  progress.on_finish(now, result);
  std::rewind(out);
  char line[256] = {};
  const bool read = std::fgets(line, sizeof line, out) != nullptr;
  std::fclose(out);
  return read ? std::string(line) : std::string();
}

ballagg::State<2> spheres_in_a_row(int n) {
  std::vector<ballagg::testing::Ball<2>> balls;
  for (int k = 0; k < n; ++k) balls.push_back({ballagg::Vec<2>(1.0 + 2.0 * k, 1.0), ballagg::Vec<2>(0.0, 0.0)});
  return ballagg::testing::make_state<2>(2.0 * n + 2.0, ballagg::Boundary::walls, balls);
}

TEST(Progress, FollowsStopTimeWhenItIsSetNotTheClusters) {
  // Half the clusters gone at a tenth of stop.time (Richardson's model v removes half of
  // them by t = 2.25 of 40.8): a run cut there by the wall clock says 10%, not 53%.
  const ballagg::State<2> start = spheres_in_a_row(20);
  ballagg::State<2> now = spheres_in_a_row(10);
  now.time = 1.0;
  ballagg::StopCriteria stop;
  stop.time = 10.0;
  stop.clusters = 1;
  EXPECT_EQ(progress_line(start, now, stop, ballagg::StopReason::wall_seconds).substr(0, 4), " 10%");
  // A run that another criterion ended is done.
  EXPECT_EQ(progress_line(start, now, stop, ballagg::StopReason::clusters).substr(0, 4), "100%");
  // Without stop.time, the clusters removed: (20 - 10) / (20 - 1).
  stop.time = std::numeric_limits<double>::infinity();
  EXPECT_EQ(progress_line(start, now, stop, ballagg::StopReason::wall_seconds).substr(0, 4), " 53%");
}
