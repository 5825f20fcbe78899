// Sweeps: the sweep file (grid, variants, realizations) and its errors with file lines,
// an exact small sweep whose tables are checked against the runs' own files, resuming
// without redoing finished runs, two MPI ranks giving the same results as one process,
// and the analyze and plot commands on their outputs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "ballagg/sweep/sweep_runner.hpp"
#include "ballagg/sweep/sweep_spec.hpp"
#include "ballagg/sweep/sweep_table.hpp"
#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using ballagg::InputError;
using ballagg::testing::slurp;
using ballagg::testing::run_ballagg;
using ballagg::testing::TempDir;

namespace {

// 16 or 25 discs with walls (a few milliseconds each), two realizations.
const char* kTinySweep = R"(# a tiny sweep
[sweep]
realizations = 2
seed_base = 40

[grid]
system.n = [16, 25]
system.volume_fraction = [0.2]
)";

std::string sweep_error(const std::string& text) {
  try {
    const ballagg::SweepSpec spec = ballagg::parse_sweep_text(text, "s.toml");
    ballagg::sweep_runs(spec, ballagg::sweep_points(spec));
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected InputError for:\n" << text;
  return {};
}

// A CSV file as rows of column -> text.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  std::istringstream in(slurp(p));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  for (std::stringstream h(line); std::getline(h, line, ',');) header.push_back(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::stringstream fields(line);
    for (const std::string& name : header) {
      std::string f;
      std::getline(fields, f, ',');
      row[name] = f;
    }
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

ballagg::SweepOutcome run_tiny_sweep(const fs::path& out, bool resume = false, const char* text = kTinySweep) {
  const ballagg::Communicator world;
  ballagg::SweepOptions o;
  o.out_dir = out.string();
  o.resume = resume;
  o.jobs = 2;
  o.quiet = true;
  return ballagg::run_sweep(ballagg::parse_sweep_text(text, "tiny.toml"), o, world);
}

}  // namespace

TEST(SweepFile, VariantsTimesGridFirstAxisSlowest) {
  const auto spec = ballagg::parse_sweep_text(R"(
[sweep]
realizations = 3
seed_base = 100
[grid]
system.n = [100, 400]
ts.dt_factor = [0.005, 0.01]
[[variants]]
engine.kind = "ed"
[[variants]]
label = "ts rigid"
engine.kind = "ts"
ts.model = "rigid"
)", "s.toml");
  const auto points = ballagg::sweep_points(spec);
  ASSERT_EQ(points.size(), 8u);
  EXPECT_EQ(points[0].variant->label, "engine.kind=\"ed\"");
  EXPECT_EQ(points[5].variant->label, "ts rigid");
  EXPECT_EQ(points[1].values[0]->value, "100");
  EXPECT_EQ(points[1].values[1]->value, "0.01");
  EXPECT_EQ(points[2].values[0]->value, "400");
  const auto runs = ballagg::sweep_runs(spec, points);
  ASSERT_EQ(runs.size(), 24u);
  // The same seeds at every point: realization k of ED and TS start from the same state.
  EXPECT_EQ(runs[0].seed, 100u);
  EXPECT_EQ(runs[2].seed, 102u);
  EXPECT_EQ(runs[23].seed, 102u);
  EXPECT_EQ(runs[23].name, "p007-r02");
  EXPECT_EQ(runs[23].config.engine.kind, ballagg::EngineKind::ts);
  EXPECT_EQ(runs[23].config.system.n, 400);
  EXPECT_DOUBLE_EQ(runs[23].config.ts.dt_factor, 0.01);
}

TEST(SweepFile, AVariantsArrayReplacesTheGridValuesOfItsKey) {
  // The costly per-sphere models on the smaller N only.
  const auto spec = ballagg::parse_sweep_text(R"([grid]
system.n = [100, 400, 10000]
system.volume_fraction = [0.1, 0.3]
[[variants]]
engine.kind = "ed"
[[variants]]
engine.kind = "ts"
ts.model = "non-rigid"
system.n = [100, 400]
)", "s.toml");
  const auto points = ballagg::sweep_points(spec);
  ASSERT_EQ(points.size(), 6u + 4u);
  EXPECT_EQ(points[9].values[0]->value, "400");
  EXPECT_EQ(points[9].values[1]->value, "0.3");
  EXPECT_EQ(points[9].variant->label, "engine.kind=\"ts\",ts.model=\"non-rigid\"");
  EXPECT_EQ(sweep_error("[grid]\nsystem.n = [1]\n[[variants]]\nsystem.radius = [0.1, 0.2]\n"),
            "s.toml:4: variant values for system.radius: not a key of [grid] (a variant's array replaces the grid's "
            "values for that key)");
}

TEST(SweepFile, SeedsInTheGridStartEachPointsRealizations) {
  const auto spec = ballagg::parse_sweep_text("[sweep]\nrealizations = 2\n[grid]\ninitial.seed = [7, 70]\n", "s.toml");
  const auto runs = ballagg::sweep_runs(spec, ballagg::sweep_points(spec));
  ASSERT_EQ(runs.size(), 4u);
  EXPECT_EQ(runs[1].seed, 8u);
  EXPECT_EQ(runs[3].seed, 71u);
}

TEST(SweepFile, ErrorsNameTheLine) {
  EXPECT_EQ(sweep_error("[grd]\nx = 1\n"), "s.toml:1: unknown section [grd] (a sweep file has [sweep], [grid] and [[variants]])");
  EXPECT_EQ(sweep_error("[grid]\nsystem.n = 100\n"), "s.toml:2: grid system.n must be a non-empty array of values, e.g. system.n = [1, 2]");
  EXPECT_EQ(sweep_error("[grid]\nsystem.n = []\n"), "s.toml:2: grid system.n must be a non-empty array of values, e.g. system.n = [1, 2]");
  EXPECT_EQ(sweep_error("[grid]\nn = [1, 2]\n"), "s.toml:2: grid key 'n' must be a configuration key section.key (for example system.n)");
  EXPECT_EQ(sweep_error("[grid]\nsystem.n = [100,\n  -5]\n"), "s.toml:3: system.n = -5: must be an integer from 1 to 100000000");
  EXPECT_CONTAINS(sweep_error("[grid]\n\nsystem.nn = [1]\n"), "s.toml:3: unknown key 'system.nn' (keys of [system]:");
  EXPECT_EQ(sweep_error("[sweep]\nrealizations = 0\n"), "s.toml:2: sweep.realizations must be an integer from 1 to 1000000");
  EXPECT_EQ(sweep_error("[sweep]\nseeds = 3\n"), "s.toml:2: unknown key 'sweep.seeds' (keys of [sweep]: base, realizations, seed_base)");
  EXPECT_EQ(sweep_error("[grid]\nsystem.n = [4, 4]\n"), "s.toml:2: grid system.n: the value 4 appears twice");
  EXPECT_EQ(sweep_error("[[variants]]\nengine.kind = \"ed\"\n[grid]\nengine.kind = [\"ts\"]\n"),
            "s.toml:4: grid engine.kind: also set by the variant at line 1 (set it in one place)");
  EXPECT_EQ(sweep_error("[grid]\nengine.kind = [\"warp\"]\n"),
            "s.toml:2: engine.kind = \"warp\": must be one of \"ed\", \"ed-naive\", \"ts\", \"rigid-body\"");
  EXPECT_CONTAINS(sweep_error("[grid]\nsystem.n = [1\n"), "s.toml:2: invalid TOML");
  EXPECT_CONTAINS(sweep_error("[sweep]\nbase = \"no/such/base.toml\"\n"), "no/such/base.toml: cannot read the config file");
  // A rule between keys names the grid point.
  EXPECT_CONTAINS(sweep_error("[grid]\nengine.kind = [\"ed\", \"ts\"]\ncollision.outcome = [\"bounce\"]\n"),
                  "s.toml: grid point 1 (engine.kind = \"ts\", collision.outcome = \"bounce\"):");
}

TEST(SweepStatistics, MeanAndStandardDeviationOfTheMean) {
  const auto m = ballagg::mean_and_error({1.0, 2.0, 3.0, 4.0, std::nan("")});
  EXPECT_EQ(m.count, 4);
  EXPECT_DOUBLE_EQ(m.mean, 2.5);
  EXPECT_DOUBLE_EQ(m.error, std::sqrt(5.0 / 12.0));  // sum of squares 5, over n (n - 1) = 12
  EXPECT_TRUE(std::isnan(ballagg::mean_and_error({3.0}).error));
}

TEST(Sweep, TablesAreTheMeansOfTheRunsOwnFiles) {
  TempDir dir;
  const fs::path out = dir / "sweep";
  const auto outcome = run_tiny_sweep(out);
  EXPECT_EQ(outcome.ran, 4);
  EXPECT_EQ(outcome.failed, 0);
  const auto table = read_csv(out / "sweep.csv");
  ASSERT_EQ(table.size(), 2u);
  for (int point = 0; point < 2; ++point) {
    const auto& row = table[point];
    EXPECT_EQ(row.at("system.n"), point == 0 ? "16" : "25");
    EXPECT_EQ(row.at("method"), "ed");
    EXPECT_EQ(row.at("runs"), "2");
    // By hand from the two runs' files: mean and |x1 - x2| / 2 (the error of a mean of two).
    for (const auto& [column, file, key] : {std::tuple{"wall_seconds", "summary.json", "wall_seconds"},
                                            std::tuple{"simulated_time", "summary.json", "time"}}) {
      const double a = read_json(out / "runs" / fmt::format("p{:03d}-r00", point) / file)[key].get<double>();
      const double b = read_json(out / "runs" / fmt::format("p{:03d}-r01", point) / file)[key].get<double>();
      EXPECT_NEAR(std::stod(row.at(std::string(column) + "_mean")), 0.5 * (a + b), 1e-12 * std::abs(a + b)) << column;
      EXPECT_NEAR(std::stod(row.at(std::string(column) + "_sem")), 0.5 * std::abs(a - b), 1e-12 * std::abs(a + b)) << column;
    }
    const auto a = read_json(out / "runs" / fmt::format("p{:03d}-r00", point) / "analysis.json");
    const auto b = read_json(out / "runs" / fmt::format("p{:03d}-r01", point) / "analysis.json");
    const double ca = a["all_spheres"]["contacts"].get<double>(), cb = b["all_spheres"]["contacts"].get<double>();
    EXPECT_NEAR(std::stod(row.at("contacts_mean")), 0.5 * (ca + cb), 1e-12);
    // Realization k has seed seed_base + k at every point.
    EXPECT_EQ(read_json(out / "runs" / fmt::format("p{:03d}-r01", point) / "summary.json")["seed"], 41);
  }
  EXPECT_EQ(read_csv(out / "runs.csv").size(), 4u);
  EXPECT_FALSE(read_csv(out / "sweep_box_counting.csv").empty());
  EXPECT_EQ(read_csv(out / "sweep_pair_distribution.csv").size(), 2u * 65u);
}

TEST(Sweep, RunsCutByTheirTimeLimitAreLeftOutOfTheMeans) {
  // stop.wall_seconds = 1e-9: every run stops at its first check, far from one cluster.
  TempDir dir;
  const fs::path out = dir / "sweep";
  const std::string text = std::string(kTinySweep) + "stop.wall_seconds = [1e-9]\n";
  run_tiny_sweep(out, false, text.c_str());
  const auto table = read_csv(out / "sweep.csv");
  ASSERT_EQ(table.size(), 2u);
  EXPECT_EQ(table[0].at("runs"), "0");
  EXPECT_EQ(table[0].at("runs_cut"), "2");
  EXPECT_EQ(table[0].at("wall_seconds_mean"), "nan");
  const auto runs = read_csv(out / "runs.csv");
  ASSERT_EQ(runs.size(), 4u);
  EXPECT_EQ(runs[0].at("stop_reason"), "wall_seconds");
}

TEST(Sweep, ResumeRedoesOnlyTheRunsWithoutSummary) {
  TempDir dir;
  const fs::path out = dir / "sweep";
  run_tiny_sweep(out);
  // A sweep killed during run p001-r00: its summary.json (written last) is missing.
  fs::remove(out / "runs" / "p001-r00" / "summary.json");
  std::map<std::string, fs::file_time_type> before;
  for (const char* run : {"p000-r00", "p000-r01", "p001-r01"})
    before[run] = fs::last_write_time(out / "runs" / run / "summary.json");
  EXPECT_THROW(run_tiny_sweep(out), InputError);  // not without --resume
  const auto outcome = run_tiny_sweep(out, true);
  EXPECT_EQ(outcome.ran, 1);
  EXPECT_EQ(outcome.skipped, 3);
  for (const auto& [run, time] : before) EXPECT_EQ(fs::last_write_time(out / "runs" / run / "summary.json"), time) << run;
  EXPECT_TRUE(fs::exists(out / "runs" / "p001-r00" / "summary.json"));
  EXPECT_EQ(read_csv(out / "sweep.csv")[1].at("runs"), "2");
  // A different grid cannot resume this sweep.
  std::string changed = kTinySweep;
  changed.replace(changed.find("[16, 25]"), 8, "[16, 36]");
  try {
    run_tiny_sweep(out, true, changed.c_str());
    ADD_FAILURE() << "a changed sweep file was resumed";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "the file this sweep was started with");
  }
}

// Two variants times two grid values times two realizations: 8 runs of 16 or 25 discs.
const char* kVariantSweep = R"([sweep]
realizations = 2
seed_base = 40
[grid]
system.n = [16, 25]
system.volume_fraction = [0.2]
[[variants]]
label = "event driven"
engine.kind = "ed"
[[variants]]
label = "naive"
engine.kind = "ed-naive"
)";

TEST(Sweep, RunsCsvHasAColumnPerGridKey) {
  TempDir dir;
  run_tiny_sweep(dir / "sweep");
  const std::string text = slurp(dir / "sweep" / "runs.csv");
  EXPECT_EQ(text.substr(0, text.find('\n')).rfind("point,system.n,system.volume_fraction,realization,seed,run,stop_reason,"
                                                   "wall_seconds,", 0), 0u) << text;
  const auto runs = read_csv(dir / "sweep" / "runs.csv");
  ASSERT_EQ(runs.size(), 4u);
  for (const auto& row : runs) {
    EXPECT_EQ(row.at("system.n"), row.at("point") == "0" ? "16" : "25");
    EXPECT_EQ(row.at("system.volume_fraction"), "0.2");
    EXPECT_EQ(row.at("run"), fmt::format("p00{}-r0{}", row.at("point"), row.at("realization")));
  }
}

TEST(SweepCli, ProgressLinesNameTheRunItsParametersAndTheTimeLeft) {
  TempDir dir;
  const fs::path file = dir.write("variants.toml", kVariantSweep);
  const auto o = run_ballagg({"sweep", file.string(), "--out", (dir / "s").string(), "--jobs", "2"}, dir.path());
  ASSERT_EQ(o.status, 0) << o.err;
  std::vector<std::string> lines;
  std::istringstream in(o.out);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 10u) << o.out;
  EXPECT_EQ(lines.front(), "sweep: 8 runs to do, 0 finished already, 2 at once");
  const std::regex done(R"(sweep: \[(\d)/8\]( (?:about \d+ s|under 1 s) left \(estimate\);)? runs/p00(\d)-r0(\d) \()"
                        R"((event driven|naive): system\.n = (16|25), system\.volume_fraction = 0\.2\) done)");
  std::set<std::string> seen;
  for (int k = 1; k <= 8; ++k) {
    std::smatch m;
    ASSERT_TRUE(std::regex_match(lines[k], m, done)) << lines[k];
    EXPECT_EQ(m[1], std::to_string(k));
    EXPECT_EQ(m[2].matched, k < 8) << lines[k];  // an estimate while runs are left
    const int point = std::stoi(m[3]);
    EXPECT_EQ(m[5], point < 2 ? "event driven" : "naive") << lines[k];
    EXPECT_EQ(m[6], point % 2 == 0 ? "16" : "25") << lines[k];
    seen.insert(std::string(m[3]) + m[4].str());
  }
  EXPECT_EQ(seen.size(), 8u);
  EXPECT_EQ(lines.back().rfind("sweep: 8 runs done, 0 already finished, 0 failed; tables in ", 0), 0u);
  // runs.csv names each run's variant and grid values.
  const std::string text = slurp(dir / "s" / "runs.csv");
  EXPECT_EQ(text.rfind("point,variant,system.n,system.volume_fraction,realization,seed,run,stop_reason,", 0), 0u) << text;
  const auto runs = read_csv(dir / "s" / "runs.csv");
  ASSERT_EQ(runs.size(), 8u);
  for (const auto& row : runs) {
    const int point = std::stoi(row.at("point"));
    EXPECT_EQ(row.at("variant"), point < 2 ? "event driven" : "naive");
    EXPECT_EQ(row.at("system.n"), point % 2 == 0 ? "16" : "25");
    EXPECT_EQ(row.at("seed"), std::to_string(40 + std::stoi(row.at("realization"))));
  }
}

TEST(SweepCli, QuietLeavesOnlyTheLastLine) {
  TempDir dir;
  const fs::path file = dir.write("tiny.toml", kTinySweep);
  const auto o = run_ballagg({"sweep", file.string(), "--out", (dir / "s").string(), "-q"}, dir.path());
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(o.out, fmt::format("sweep: 4 runs done, 0 already finished, 0 failed; tables in {}\n",
                               (dir / "s" / "sweep.csv").string()));
  EXPECT_EQ(o.err, "");
}

TEST(SweepCli, TwoMpiRanksGiveTheRunsOfOneProcess) {
  if (std::system("command -v mpirun >/dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed (scripts/setup)";
  TempDir dir;
  const fs::path file = dir.write("tiny.toml", kTinySweep);
  const auto serial = run_ballagg({"sweep", file.string(), "--out", (dir / "one").string(), "-q"}, dir.path());
  ASSERT_EQ(serial.status, 0) << serial.err;
  // Under `make sanitize`, the ranks are checked for memory errors but not for leaks: Open
  // MPI leaves its own allocations at MPI_Finalize, in plugins unloaded by then (nothing
  // there to fix or even name; the serial sweep above is leak-checked).
  const auto mpi = run_ballagg({"sweep", file.string(), "--out", (dir / "two").string(), "-q"}, dir.path(),
                               "env ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" "
                               "mpirun --allow-run-as-root --oversubscribe -np 2");
  ASSERT_EQ(mpi.status, 0) << mpi.err << mpi.out;
  EXPECT_CONTAINS(mpi.out, "sweep: 4 runs done, 0 already finished, 0 failed");
  for (const char* run : {"p000-r00", "p000-r01", "p001-r00", "p001-r01"}) {
    EXPECT_EQ(slurp(dir / "one" / "runs" / run / "final.csv"), slurp(dir / "two" / "runs" / run / "final.csv"));
    EXPECT_EQ(slurp(dir / "one" / "runs" / run / "clusters.csv"), slurp(dir / "two" / "runs" / run / "clusters.csv"));
  }
  EXPECT_EQ(read_csv(dir / "two" / "sweep.csv").size(), 2u);
}

TEST(SweepCli, BadSweepFileExitsWithStatus2AndOneLine) {
  TempDir dir;
  const fs::path file = dir.write("bad.toml", "[sweep]\nrealizations = 2\n[grid]\nsystem.radius = [0.2, -1]\n");
  const auto o = run_ballagg({"sweep", file.string(), "--out", (dir / "s").string()}, dir.path());
  EXPECT_EQ(o.status, 2);
  EXPECT_EQ(o.err, fmt::format("ballagg: error: {}:4: system.radius = -1: must be a number > 0\n", file.string()));
  EXPECT_FALSE(fs::exists(dir / "s"));
}

TEST(AnalyzeCli, WritesTheTablesOfARun) {
  TempDir dir;
  const fs::path run = dir / "run";
  ASSERT_EQ(run_ballagg({"run", "-q", "--out", run.string(), "--set", "system.n=100"}, dir.path()).status, 0);
  const auto o = run_ballagg({"analyze", run.string()}, dir.path());
  ASSERT_EQ(o.status, 0) << o.err;
  const auto a = read_json(run / "analysis.json");
  EXPECT_EQ(a["n_spheres"], 100);
  EXPECT_EQ(a["largest_cluster"]["size"], 100);
  // One cluster: the box's indicators are the cluster's.
  EXPECT_EQ(a["all_spheres"]["contacts"], a["largest_cluster"]["contacts"]);
  EXPECT_DOUBLE_EQ(a["all_spheres"]["contacts_with_self"].get<double>(), a["all_spheres"]["contacts"].get<double>() + 1.0 / 6);
  for (const char* f : {"clusters.csv", "mass_spectrum.csv", "box_counting.csv", "pair_distribution.csv", "mass_radius.csv"})
    EXPECT_TRUE(fs::exists(run / f)) << f;
  EXPECT_EQ(slurp(run / "mass_spectrum.csv"), "size,mass,clusters\n100,100,1\n");
  // Any state file in the format, with the configuration that gives its box.
  const auto again = run_ballagg({"analyze", "--state", (run / "final.csv").string(), "--config",
                                              (run / "config.toml").string(), "--out", (dir / "other").string()}, dir.path());
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(slurp(dir / "other" / "clusters.csv"), slurp(run / "clusters.csv"));
}

TEST(AnalyzeCli, StateOutsideTheConfiguredBoxIsBadInput) {
  TempDir dir;
  const fs::path run = dir / "run";
  ASSERT_EQ(run_ballagg({"run", "-q", "--out", run.string(), "--set", "system.n=100"}, dir.path()).status, 0);
  const fs::path small = dir.write("small.toml", "[system]\nbox_length = 2.0\n");
  const auto o = run_ballagg({"analyze", run.string(), "--config", small.string()}, dir.path());
  EXPECT_EQ(o.status, 2);
  EXPECT_CONTAINS(o.err, "centre outside the box [0, 2]");
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1);
  EXPECT_FALSE(fs::exists(run / "analysis.json"));
  const auto missing = run_ballagg({"analyze", (dir / "nothing").string()}, dir.path());
  EXPECT_EQ(missing.status, 2);
  EXPECT_CONTAINS(missing.err, "not a run directory");
}

TEST(PlotCli, DrawsTheFiguresOfASweep) {
  // 100 and 144 discs: the smallest boxes with three box-counting levels, so that D_f is
  // reported (with 16 and 25 it is withheld and its figure is not drawn).
  TempDir dir;
  std::string text = kTinySweep;
  text.replace(text.find("[16, 25]"), 8, "[100, 144]");
  run_tiny_sweep(dir / "sweep", false, text.c_str());
  const auto o = run_ballagg({"plot", (dir / "sweep").string()}, dir.path());
  ASSERT_EQ(o.status, 0) << o.err;
  for (const char* f : {"wall_time.png", "contacts.png", "pair_distribution.png", "box_counting.png",
                        "fractal_dimension.png", "aspect_ratio.png", "orientation.png"}) {
    const fs::path png = dir / "sweep" / "figures" / f;
    ASSERT_TRUE(fs::exists(png)) << f;
    EXPECT_EQ(slurp(png).substr(1, 3), "PNG") << f;
  }
  const auto bad = run_ballagg({"plot", dir.path().string()}, dir.path());
  EXPECT_EQ(bad.status, 2);
  EXPECT_CONTAINS(bad.err, "sweep.csv: missing");
  // An --out that cannot be a directory: one line, status 2, no figure drawn.
  const fs::path file = dir.write("figures.txt", "not a directory\n");
  const auto not_a_dir = run_ballagg({"plot", (dir / "sweep").string(), "--out", file.string()}, dir.path());
  EXPECT_EQ(not_a_dir.status, 2);
  EXPECT_EQ(not_a_dir.err, fmt::format("ballagg plot: error: --out {}: exists and is not a directory\n", file.string()));
  EXPECT_EQ(not_a_dir.out, "");
}

TEST(SweepFile, CommittedSweepFilesAreValid) {
  // bench/paper_table1_*.toml (the reproduction of docs/validation.md) and the README's
  // examples/sweeps/ must stay runnable.
  int seen = 0;
  for (const char* folder : {"/bench", "/examples/sweeps"}) {
    for (const auto& entry : fs::directory_iterator(std::string(BALLAGG_SOURCE_DIR) + folder)) {
      if (entry.path().extension() != ".toml") continue;
      SCOPED_TRACE(entry.path().string());
      const ballagg::SweepSpec spec = ballagg::load_sweep(entry.path().string());
      EXPECT_FALSE(ballagg::sweep_runs(spec, ballagg::sweep_points(spec)).empty());
      ++seen;
    }
  }
  EXPECT_GE(seen, 3);
}

// Found while writing the fuzz targets: toml++ recursed over a dotted key 100000 parts
// deep until the stack overflowed (a segmentation fault instead of an error).
TEST(SweepSpec, AbsurdlyDeepDottedKeyIsAnErrorNotAStackOverflow) {
  std::string deep;
  for (int k = 0; k < 100000; ++k) deep += "a.";
  try {
    ballagg::parse_sweep_text(deep + "b = 1\n", "deep.toml");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("deep.toml:1: more than 4096 dotted key parts"), std::string::npos) << e.what();
  }
}
