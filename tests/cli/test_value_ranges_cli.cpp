// Finite but extreme values through the binary: radii, masses, speeds, skins and boxes
// whose arithmetic would overflow or lose all precision end with the bad-input contract
// (exit status 2, one line on stderr naming the key or the file line and the allowed
// range, no output directory), and runs at the corners of the allowed ranges finish with
// finite totals in every engine.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;

namespace {

using ballagg::testing::Outcome;
using ballagg::testing::slurp;
using ballagg::testing::TempDir;

class ExtremeValues : public ::testing::Test {
 protected:
  Outcome run(const std::vector<std::string>& args) const { return ballagg::testing::run_ballagg(args, dir_.path()); }

  // `ballagg run --quiet --out DIR --set ...` must refuse with one line holding every needle.
  void expect_refused(const std::vector<std::string>& sets, const std::vector<std::string>& needles) const {
    const fs::path out = dir_ / "o";
    std::vector<std::string> args{"run", "--quiet", "--out", out.string()};
    for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
    const Outcome o = run(args);
    EXPECT_EQ(o.status, 2) << "stderr: " << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << "stderr: " << o.err;
    EXPECT_EQ(o.err.rfind("ballagg: error: ", 0), 0u) << "stderr: " << o.err;
    for (const std::string& n : needles) EXPECT_CONTAINS(o.err, n);
    EXPECT_EQ(o.out, "");
    EXPECT_FALSE(fs::exists(out)) << out << " was created";
  }

  TempDir dir_;
};

TEST_F(ExtremeValues, HugeOrTinyRadiiAreRefusedBeforeAnythingIsWritten) {
  expect_refused({"system.dimension=3", "system.radius=1e102", "system.n=1"},
                 {"--set system.radius", "from 1e-20 to 1e+20"});
  expect_refused({"system.dimension=3", "system.radius=1e102"}, {"--set system.radius"});
  expect_refused({"system.radius=1e155"}, {"--set system.radius", "from 1e-20 to 1e+20"});
  expect_refused({"engine.kind=rigid-body", "system.dimension=3", "system.radius=1e103"}, {"--set system.radius"});
  expect_refused({"system.radius=1e-300"}, {"--set system.radius", "from 1e-20 to 1e+20"});
}

TEST_F(ExtremeValues, HugeMassesAndSpeedsAreRefused) {
  expect_refused({"system.n=100", "system.mass=1e307", "stop.wall_seconds=2"},
                 {"--set system.mass", "from 1e-30 to 1e+30"});
  expect_refused({"system.n=4", "system.mass=1e308", "stop.time=100"}, {"--set system.mass"});
  expect_refused({"initial.speed=1e300"}, {"--set initial.speed", "at most 1e+20"});
}

TEST_F(ExtremeValues, AStateFileRowWithAHugeSpeedIsRefusedWithItsLine) {
  const fs::path state = dir_.write("state.csv", "x,y,vx,vy,radius,mass\n1,1,0,0,0.2,1\n5,5,1e308,0,0.2,1\n");
  expect_refused({"initial.positions=file", "initial.file=" + state.string(), "system.box_length=10"},
                 {state.string() + ":3: columns vx,vy: the speed 1e+308 is above 1e+20"});
}

TEST_F(ExtremeValues, ASkinBelowTheResolutionOfPositionsIsRefused) {
  expect_refused({"engine.skin=1e-300"}, {"--set engine.skin", "must be from 2e-07"});
  expect_refused({"engine.kind=rigid-body", "engine.skin=1e-300"}, {"--set engine.skin"});
}

TEST_F(ExtremeValues, ABoxTooLongForItsRadiusIsRefused) {
  expect_refused({"system.volume_fraction=1e-12"}, {"--set system.volume_fraction", "must be at least 7.86e-09"});
}

// Tiny runs at the corners of the allowed ranges (all bounds high, all low, and mixed) in
// 3D: every engine finishes, and every total of summary.json is a finite number.
class ExtremeValuesInRange : public ExtremeValues, public ::testing::WithParamInterface<std::string> {};

TEST_P(ExtremeValuesInRange, RunsAtTheBoundsOfTheRangesGiveFiniteTotals) {
  struct Corner {
    std::string radius, mass, speed, time;
  };
  const std::vector<Corner> corners = {{"1e20", "1e30", "1e20", "10"}, {"1e-20", "1e-30", "1e-20", "10"},
                                       {"1e20", "1e-30", "1e-20", "1e41"}, {"1e-20", "1e30", "1e20", "1e-39"}};
  const std::string engine = GetParam();
  for (const Corner& k : corners) {
    SCOPED_TRACE(engine + " radius " + k.radius + " mass " + k.mass + " speed " + k.speed);
    const fs::path out = dir_ / ("run-" + k.radius + "-" + k.mass);
    const Outcome o = run({"run", "--quiet", "--out", out.string(), "--set", "engine.kind=" + engine, "--set",
                           "system.dimension=3", "--set", "system.n=30", "--set", "system.radius=" + k.radius, "--set",
                           "system.mass=" + k.mass, "--set", "initial.speed=" + k.speed, "--set", "stop.time=" + k.time});
    ASSERT_EQ(o.status, 0) << o.err;
    const nlohmann::json j = nlohmann::json::parse(slurp(out / "summary.json"));
    EXPECT_GT(j["collisions"].get<int>(), 0);
    for (const auto& [key, value] : j.items()) {
      if (key == "config") continue;
      const std::vector<nlohmann::json> numbers = value.is_array() ? value.get<std::vector<nlohmann::json>>()
                                                                    : std::vector<nlohmann::json>{value};
      for (const nlohmann::json& v : numbers) {
        EXPECT_FALSE(v.is_null()) << key;
        if (v.is_number()) {
          EXPECT_TRUE(std::isfinite(v.get<double>())) << key;
        }
      }
    }
    EXPECT_GT(j["kinetic_energy_initial"].get<double>(), 0.0);
    EXPECT_GT(j["mass_total"].get<double>(), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryEngine, ExtremeValuesInRange, ::testing::Values("ed", "ed-naive", "ts", "rigid-body"),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                           std::string name = p.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
