// `ballagg analyze --kinetics`: the exponents of a real run's time series over the
// automatic window and a given one, and the scaling collapse of its frames.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ballagg/config/config.hpp"
#include "ballagg/core/input_error.hpp"
#include "ballagg/run/analyze_frames.hpp"
#include "ballagg/run/analyze_kinetics.hpp"
#include "ballagg/run/simulation.hpp"
#include "file_text.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::TempDir;

using testing::slurp;

// A dilute 2D gas of 3000 discs to 20 clusters, frames every 40 time units.
void dilute_run(const std::filesystem::path& dir) {
  run_simulation(parse_config_text(R"(
[system]
n = 3000
volume_fraction = 0.02
boundary = "periodic"
[initial]
positions = "random"
velocities = "gaussian"
zero_momentum = true
[stop]
clusters = 20
[output]
xyz = false
snapshot_every = 40
)", "dilute.toml"), {dir.string(), true, false});
}

TEST(AnalyzeKinetics, ExponentsOfARunAndTheCollapseOfItsFrames) {
  TempDir dir;
  const auto run = dir / "run";
  dilute_run(run);
  int frames = 0;
  analyze_frames({run.string(), "", {}}, frames);
  analyze_kinetics({run.string(), "", std::nullopt});
  const nlohmann::json k = nlohmann::json::parse(slurp(run / "kinetics.json"));
  EXPECT_TRUE(k["window"]["automatic"].get<bool>());
  const double z = k["clusters_decay_z"]["exponent"].get<double>();
  // Fractal clusters in 2D: z near the mean-field value of their dimension, ~1.
  EXPECT_GT(z, 0.6);
  EXPECT_LT(z, 1.6);
  EXPECT_GT(k["clusters_decay_z"]["exponent_error"].get<double>(), 0.0);
  EXPECT_GT(k["energy_decay_theta"]["exponent"].get<double>(), 0.0);
  EXPECT_EQ(k["clusters_decay_z"]["flaw"], "ok");
  // Each frame's collapsed distribution: sum of y is S (= sum of S^2 n_k / N with n = N / S).
  std::istringstream csv(slurp(run / "kinetics_collapse.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "time,size,clusters,mean_size,scaled_size,scaled_count");
  std::map<double, std::pair<double, double>> sums;  // time -> (sum y, S)
  while (std::getline(csv, line)) {
    std::vector<double> v;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) v.push_back(std::stod(cell));
    sums[v[0]].first += v[5];
    sums[v[0]].second = v[3];
  }
  EXPECT_EQ(static_cast<int>(sums.size()), frames);
  for (const auto& [t, s] : sums) EXPECT_NEAR(s.first, s.second, 1e-9 * s.second) << t;
  // A given window is used as given.
  analyze_kinetics({run.string(), (dir / "w").string(), std::pair{50.0, 400.0}});
  const nlohmann::json w = nlohmann::json::parse(slurp(dir / "w" / "kinetics.json"));
  EXPECT_FALSE(w["window"]["automatic"].get<bool>());
  EXPECT_EQ(w["window"]["start"].get<double>(), 50.0);
}

TEST(AnalyzeKinetics, ABadWindowIsRefusedBeforeWriting) {
  TempDir dir;
  for (auto window : {std::pair{5.0, 1.0}, std::pair{0.0, 1.0}, std::pair{1.0, std::nan("")}})
    EXPECT_THROW(analyze_kinetics({(dir / "nowhere").string(), (dir / "out").string(), window}), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

}  // namespace
}  // namespace ballagg
