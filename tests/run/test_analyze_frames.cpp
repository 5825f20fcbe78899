// `ballagg analyze --frames`: the indicators of every frame of a trajectory against time.
// The last frame of a run is its final state, so its row must repeat the final-state
// analysis exactly; chosen times pick the nearest frames; a run without a trajectory is
// refused before anything is written.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ballagg/config/config.hpp"
#include "ballagg/core/input_error.hpp"
#include "ballagg/run/analyze_frames.hpp"
#include "ballagg/run/analyze_run.hpp"
#include "ballagg/run/simulation.hpp"
#include "file_text.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::TempDir;

using testing::slurp;

// A 2D run to one cluster with a frame every 5 time units (and one at the end), stored in
// double precision: the frames hold the very positions final.csv holds.
Config run_with_frames(const std::string& formats = "[\"h5md\"]") {
  return parse_config_text(R"(
[system]
n = 300
volume_fraction = 0.1
boundary = "periodic"
[initial]
positions = "random"
[output]
xyz = false
snapshot_every = 5
snapshot_precision = "double"
snapshot_formats = )" + formats + "\n", "frames.toml");
}

// Rows of a CSV file as maps from column to text.
std::vector<std::map<std::string, std::string>> rows_of(const std::filesystem::path& p) {
  std::istringstream in(slurp(p));
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> header;
  for (std::istringstream h(line); std::getline(h, cell, ',');) header.push_back(cell);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::istringstream r(line);
    for (const std::string& name : header) {
      std::getline(r, cell, ',');
      row[name] = cell;
    }
    rows.push_back(row);
  }
  return rows;
}

double as_number(const nlohmann::json& j) { return j.is_null() ? std::nan("") : j.get<double>(); }

void expect_same_number(const std::string& text, const nlohmann::json& j, const char* what) {
  const double v = std::stod(text), w = as_number(j);
  if (std::isnan(w)) {
    EXPECT_TRUE(std::isnan(v)) << what;
  } else {
    EXPECT_EQ(v, w) << what;
  }
}

TEST(AnalyzeFrames, TheLastFrameRepeatsTheFinalStateAnalysis) {
  TempDir dir;
  run_simulation(run_with_frames(), {(dir / "run").string(), true, false});
  analyze_run({(dir / "run").string(), "", "", ""});
  int frames = 0;
  analyze_frames({(dir / "run").string(), "", {}}, frames);
  const auto rows = rows_of(dir / "run" / "frames.csv");
  const nlohmann::json a = nlohmann::json::parse(slurp(dir / "run" / "analysis.json"));
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir / "run" / "summary.json"));
  ASSERT_EQ(static_cast<int>(rows.size()), frames);
  ASSERT_GE(frames, 3);
  const auto& last = rows.back();
  EXPECT_EQ(std::stod(last.at("time")), summary["time"].get<double>());
  EXPECT_EQ(std::stoi(last.at("n_clusters")), a["n_clusters"].get<int>());
  expect_same_number(last.at("contacts"), a["all_spheres"]["contacts"], "contacts");
  expect_same_number(last.at("box_counting_dimension"), a["all_spheres"]["box_counting"]["dimension"], "D_f");
  expect_same_number(last.at("box_counting_dimension_error"), a["all_spheres"]["box_counting"]["dimension_error"], "D_f error");
  expect_same_number(last.at("largest_mass_radius_dimension"), a["largest_cluster"]["mass_radius_dimension"], "mass-radius");
  expect_same_number(last.at("largest_aspect_ratio"), a["largest_cluster"]["aspect_ratio"], "A_r");
  expect_same_number(last.at("heaviest_mass_fraction"), a["heaviest_mass_fraction"], "heaviest");
  // The first frame is the initial state: every sphere on its own.
  EXPECT_EQ(std::stod(rows.front().at("time")), 0.0);
  EXPECT_EQ(rows.front().at("n_clusters"), "300");
  EXPECT_EQ(rows.front().at("weight_average_mass"), "1");
  // Cluster counts never rise in an aggregating run, and the spectrum adds up to them.
  for (std::size_t k = 1; k < rows.size(); ++k)
    EXPECT_LE(std::stoi(rows[k].at("n_clusters")), std::stoi(rows[k - 1].at("n_clusters")));
  std::map<std::string, long> clusters_at;
  for (const auto& b : rows_of(dir / "run" / "frames_mass_spectrum.csv")) clusters_at[b.at("time")] += std::stol(b.at("clusters"));
  for (const auto& r : rows) EXPECT_EQ(clusters_at[r.at("time")], std::stol(r.at("n_clusters"))) << r.at("time");
}

TEST(AnalyzeFrames, ChosenTimesPickTheNearestFramesOnce) {
  EXPECT_EQ(frames_nearest({0, 5, 10, 12.5}, {7, 2.5, 100, -3, 7.4}), (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(frames_nearest({0, 5, 10}, {7.5}), (std::vector<int>{1}));  // a tie takes the earlier
  EXPECT_TRUE(frames_nearest({}, {1.0}).empty());
}

TEST(AnalyzeFrames, ARunWithoutTrajectoryIsRefusedBeforeWriting) {
  TempDir dir;
  Config c = run_with_frames();
  c.output.snapshot_every = 0.0;
  run_simulation(c, {(dir / "run").string(), true, false});
  int frames = 0;
  try {
    analyze_frames({(dir / "run").string(), (dir / "out").string(), {}}, frames);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(std::string(e.what()), "trajectory.h5md not found");
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  EXPECT_THROW(analyze_frames({(dir / "run").string(), "", {std::nan("")}}, frames), InputError);
}

}  // namespace
}  // namespace ballagg
