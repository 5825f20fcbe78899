// A finished run's directory as the initial state (initial.file = "RUN_DIR"), initial.time,
// and `ballagg config` printing what a run resolves: end-to-end through the binary.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;

namespace {

using ballagg::testing::Outcome;
using ballagg::testing::slurp;

class ContinueRun : public ::testing::Test {
 protected:
  fs::path path(const std::string& name) const { return dir_ / name; }
  Outcome run(const std::vector<std::string>& args) const { return ballagg::testing::run_ballagg(args, dir_.path()); }

  // `ballagg run -q ARGS --out OUT`, which must succeed.
  void run_ok(const std::string& out, std::vector<std::string> args) const {
    args.insert(args.begin(), {"run", "-q"});
    args.insert(args.end(), {"--out", path(out).string()});
    const Outcome o = run(args);
    ASSERT_EQ(o.status, 0) << o.err;
  }

  // The arguments that continue the run in directory `from`.
  std::vector<std::string> continuing(const std::string& from) const {
    return {"--set", "initial.positions=file", "--set", "initial.file=" + path(from).string()};
  }

  nlohmann::json summary(const std::string& run_dir) const {
    return nlohmann::json::parse(slurp(path(run_dir) / "summary.json"));
  }

  // The bad-input contract: status 2, one line naming every needle, no output directory.
  void expect_refused(std::vector<std::string> args, const std::vector<std::string>& needles) const {
    args.insert(args.begin(), {"run", "-q"});
    args.insert(args.end(), {"--out", path("refused").string()});
    const Outcome o = run(args);
    EXPECT_EQ(o.status, 2) << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
    EXPECT_EQ(o.err.rfind("ballagg: error: ", 0), 0u) << o.err;
    for (const std::string& n : needles) EXPECT_CONTAINS(o.err, n);
    EXPECT_FALSE(fs::exists(path("refused")));
  }

  ballagg::testing::TempDir dir_{"ballagg-continue-"};
};

// timeseries.csv's first column.
std::vector<double> times(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  std::vector<double> t;
  while (std::getline(in, line)) t.push_back(std::stod(line.substr(0, line.find(','))));
  return t;
}

// The largest difference between two final.csv files of the same spheres, field by field.
double largest_difference(const std::string& a, const std::string& b) {
  std::istringstream ia(a), ib(b);
  std::string la, lb;
  double largest = 0.0;
  std::getline(ia, la);
  std::getline(ib, lb);
  EXPECT_EQ(la, lb);  // the same columns
  while (std::getline(ia, la)) {
    if (!std::getline(ib, lb)) return INFINITY;
    std::istringstream fa(la), fb(lb);
    std::string x, y;
    while (std::getline(fa, x, ',') && std::getline(fb, y, ','))
      largest = std::max(largest, std::abs(std::stod(x) - std::stod(y)));
  }
  return std::getline(ib, lb) ? INFINITY : largest;
}

const std::vector<std::string> kPeriodicDiscs = {"--set", "system.n=100", "--set", "system.boundary=periodic",
                                                 "--set", "output.timeseries_interval=0.5"};

TEST_F(ContinueRun, FromItsDirectoryToALaterStopTimeAsIfItHadNotStopped) {
  std::vector<std::string> first = kPeriodicDiscs, whole = kPeriodicDiscs, second = continuing("first");
  first.insert(first.end(), {"--set", "stop.time=2"});
  whole.insert(whole.end(), {"--set", "stop.time=4"});
  second.insert(second.end(), kPeriodicDiscs.begin(), kPeriodicDiscs.end());
  second.insert(second.end(), {"--set", "stop.time=4"});
  run_ok("first", first);
  run_ok("second", second);
  run_ok("whole", whole);

  const nlohmann::json a = summary("first"), b = summary("second");
  ASSERT_EQ(a["time"], 2.0);
  EXPECT_EQ(b["time"], 4.0);
  EXPECT_EQ(b["box_length"], a["box_length"]);
  EXPECT_EQ(b["boundary"], "periodic");
  EXPECT_EQ(b["n_particles"], 100);
  EXPECT_EQ(b["mass_total"], a["mass_total"]);
  EXPECT_LT(b["n_clusters"].get<int>(), a["n_clusters"].get<int>());
  // The clock goes on: the time series starts at the first run's end, at its state.
  const std::vector<double> t = times(slurp(path("second/timeseries.csv")));
  ASSERT_GE(t.size(), 4u);
  EXPECT_EQ(t.front(), 2.0);
  EXPECT_EQ(t.back(), 4.0);
  EXPECT_TRUE(std::is_sorted(t.begin(), t.end()));
  // Momentum is conserved across the two runs (a periodic box), and nothing overlaps.
  for (int k = 0; k < 2; ++k) {
    const double scale = std::abs(a["momentum_final"][k].get<double>()) + 1.0;
    EXPECT_NEAR(b["momentum_initial"][k].get<double>(), a["momentum_final"][k].get<double>(), 1e-13 * scale);
    EXPECT_NEAR(b["momentum_final"][k].get<double>(), a["momentum_initial"][k].get<double>(), 1e-12 * scale);
  }
  EXPECT_LT(b["max_overlap"].get<double>(), 1e-9);
  // The two runs end where one run of the whole time ends (the same events; the numbers
  // within round-off of the restart from final.csv).
  EXPECT_EQ(b["n_clusters"], summary("whole")["n_clusters"]);
  EXPECT_LT(largest_difference(slurp(path("second/final.csv")), slurp(path("whole/final.csv"))), 1e-9);
  const Outcome verified = run({"verify", path("second").string()});
  EXPECT_EQ(verified.status, 0) << verified.out << verified.err;
}

TEST_F(ContinueRun, ItsConfigTomlNamesTheStateBoxAndClockAndReproducesIt) {
  run_ok("first", {"--set", "system.n=36", "--set", "stop.time=1.5"});
  std::vector<std::string> second = continuing("first");
  second.insert(second.end(), {"--set", "stop.time=3"});
  run_ok("second", second);
  const std::string config = slurp(path("second/config.toml"));
  EXPECT_CONTAINS(config, "file = \"" + (path("first") / "final.csv").string() + "\"");
  EXPECT_CONTAINS(config, "time = 1.5\n");
  EXPECT_CONTAINS(config, fmt::format("box_length = {}\n", summary("first")["box_length"].get<double>()));
  EXPECT_EQ(config.find("volume_fraction"), std::string::npos) << config;
  run_ok("again", {path("second/config.toml").string()});
  EXPECT_EQ(slurp(path("again/final.csv")), slurp(path("second/final.csv")));
  EXPECT_EQ(slurp(path("again/timeseries.csv")), slurp(path("second/timeseries.csv")));
}

TEST_F(ContinueRun, WithTheRunsOwnConfigTomlInThreeDimensions) {
  // The run's configuration gives its box by a volume fraction: the same box, accepted.
  run_ok("first", {"--set", "system.dimension=3", "--set", "system.n=64", "--set", "stop.time=1"});
  std::vector<std::string> second{path("first/config.toml").string()};
  const std::vector<std::string> from = continuing("first");
  second.insert(second.end(), from.begin(), from.end());
  second.insert(second.end(), {"--set", "stop.time=2", "--set", "output.timeseries_interval=0.25"});
  run_ok("second", second);
  EXPECT_EQ(summary("second")["dimension"], 3);
  EXPECT_EQ(times(slurp(path("second/timeseries.csv"))).front(), 1.0);
}

TEST_F(ContinueRun, RigidBodiesKeepTheirSpins) {
  const std::vector<std::string> rigid{"--set", "engine.kind=rigid-body", "--set", "collision.mu_t=0.5",
                                       "--set", "system.n=49"};
  std::vector<std::string> first = rigid, second = continuing("first");
  first.insert(first.end(), {"--set", "stop.time=1.5"});
  second.insert(second.end(), rigid.begin(), rigid.end());
  second.insert(second.end(), {"--set", "stop.time=3"});
  run_ok("first", first);
  run_ok("second", second);
  const nlohmann::json a = summary("first"), b = summary("second");
  EXPECT_EQ(times(slurp(path("second/timeseries.csv"))).front(), 1.5);
  EXPECT_NEAR(b["rotational_energy_initial"].get<double>(), a["rotational_energy_final"].get<double>(),
              1e-12 * a["kinetic_energy_initial"].get<double>());
  EXPECT_EQ(b["mass_total"], a["mass_total"]);
}

TEST_F(ContinueRun, InitialTimeStartsTheClockOfAGeneratedState) {
  run_ok("late", {"--set", "system.n=36", "--set", "initial.time=5", "--set", "stop.time=7",
                  "--set", "output.timeseries_interval=0.5"});
  const std::vector<double> t = times(slurp(path("late/timeseries.csv")));
  EXPECT_EQ(t.front(), 5.0);
  EXPECT_EQ(t.back(), 7.0);
  EXPECT_CONTAINS(slurp(path("late/config.toml")), "time = 5.0\n");
}

TEST_F(ContinueRun, ADirectoryWithoutAFinishedRunIsRefused) {
  fs::create_directories(path("empty"));
  expect_refused(continuing("empty"), {path("empty").string(), "no summary.json"});
  run_ok("first", {"--set", "system.n=16"});
  fs::remove(path("first/summary.json"));
  expect_refused(continuing("first"), {path("first").string(), "no summary.json"});
}

TEST_F(ContinueRun, ASummaryWithoutItsBoxIsRefused) {
  run_ok("first", {"--set", "system.n=16"});
  nlohmann::json s = summary("first");
  s.erase("box_length");
  ballagg::testing::write(path("first/summary.json"), s.dump());
  expect_refused(continuing("first"), {(path("first") / "summary.json").string(), "\"box_length\" is missing"});
}

TEST_F(ContinueRun, KeysThatContradictTheRunAreRefused) {
  run_ok("first", {"--set", "system.n=16", "--set", "stop.time=1"});
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = continuing("first");
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  expect_refused(with({"--set", "system.dimension=3"}), {"--set system.dimension: system.dimension = 3", "is 2D"});
  expect_refused(with({"--set", "system.box_length=5"}), {"--set system.box_length: system.box_length = 5", "has box_length"});
  expect_refused(with({"--set", "system.boundary=periodic"}), {"system.boundary = \"periodic\"", "has boundary = \"walls\""});
  expect_refused(with({"--set", "initial.time=0.5"}), {"initial.time = 0.5", "ended at t = 1"});
  expect_refused(with({"--set", "system.volume_fraction=0.3"}), {"system.volume_fraction = 0.3", "gives a box of length"});
  // The run's own stop time: the continuation would end where it starts.
  expect_refused(with({"--set", "stop.time=1"}), {"stop.time = 1 is not after initial.time = 1", "--set stop.time=1"});
  // Keys equal to the run's are accepted.
  run_ok("second", with({"--set", "system.dimension=2", "--set", "system.boundary=walls", "--set", "initial.time=1",
                         "--set", "stop.time=2"}));
}

// ---------------------------------------------------------------------------------------
// `ballagg config` prints what `ballagg run` writes to config.toml for the same arguments.

TEST_F(ContinueRun, ConfigCommandPrintsTheResolvedConfigTomlOfTheRun) {
  for (const char* engine : {"ed", "ts", "rigid-body"}) {
    for (const char* dimension : {"2", "3"}) {
      SCOPED_TRACE(std::string(engine) + " " + dimension + "D");
      const std::string out = std::string("r-") + engine + "-" + dimension;
      const std::string outcome = std::string(engine) == "ts" ? "stick" : "bounce";  // bounces resolve tc_time
      const std::vector<std::string> sets{"--set", std::string("engine.kind=") + engine,
                                          "--set", std::string("system.dimension=") + dimension,
                                          "--set", "system.n=27", "--set", "collision.outcome=" + outcome,
                                          "--set", "stop.time=0.5"};
      std::vector<std::string> shown{"config"};
      shown.insert(shown.end(), sets.begin(), sets.end());
      const Outcome printed = run(shown);
      ASSERT_EQ(printed.status, 0) << printed.err;
      run_ok(out, sets);
      EXPECT_EQ(printed.out, slurp(path(out) / "config.toml"));
      EXPECT_CONTAINS(printed.out, std::string(engine) == "ts" ? "delta_w = " : "skin = ");
      if (outcome == "bounce") {
        EXPECT_CONTAINS(printed.out, "tc_time = ");
      }
    }
  }
}

TEST_F(ContinueRun, ConfigCommandPrintsTheContinuationOfARun) {
  run_ok("first", {"--set", "system.n=16", "--set", "stop.time=1"});
  std::vector<std::string> sets = continuing("first");
  sets.insert(sets.end(), {"--set", "stop.time=2"});
  std::vector<std::string> shown{"config"};
  shown.insert(shown.end(), sets.begin(), sets.end());
  const Outcome printed = run(shown);
  ASSERT_EQ(printed.status, 0) << printed.err;
  run_ok("second", sets);
  EXPECT_EQ(printed.out, slurp(path("second/config.toml")));
}

}  // namespace
