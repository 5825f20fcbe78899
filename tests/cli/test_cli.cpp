// End-to-end tests of the ballagg binary: commands, the files a run writes, feeding a
// final state back in, determinism, and the bad-input contract (exit status 2, one line on
// stderr naming the key or the file line, and no output directory created).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using ballagg::testing::TempDir;

namespace {

using ballagg::testing::Outcome;
using ballagg::testing::quoted;
using ballagg::testing::slurp;
using ballagg::testing::write;

// A fresh directory per test; every command runs with the binary, its output captured.
class Cli : public ::testing::Test {
 protected:
  fs::path path(const std::string& name) const { return dir_ / name; }

  // Runs `ballagg args...` (each argument quoted for the shell); a run that hangs is killed
  // after a minute and reported with status 124.
  Outcome run(const std::vector<std::string>& args) const { return ballagg::testing::run_ballagg(args, dir_); }

  // A small, fast run (16 discs, a few milliseconds) with extra arguments.
  Outcome tiny_run(const fs::path& out_dir, std::vector<std::string> extra = {}) const {
    std::vector<std::string> args{"run", "--quiet", "--out", out_dir.string(), "--set", "system.n=16"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }

  // The bad-input contract: status 2, exactly one line on stderr (containing every needle),
  // nothing on stdout, and the output directory not created.
  void expect_bad_input(const std::vector<std::string>& args, const fs::path& out_dir,
                        const std::vector<std::string>& needles) const {
    const Outcome o = run(args);
    EXPECT_EQ(o.status, 2) << "stderr: " << o.err;
    EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << "stderr: " << o.err;
    EXPECT_TRUE(!o.err.empty() && o.err.back() == '\n') << "stderr: " << o.err;
    EXPECT_EQ(o.err.rfind("ballagg: error: ", 0), 0u) << "stderr: " << o.err;
    for (const std::string& n : needles) EXPECT_CONTAINS(o.err, n);
    EXPECT_EQ(o.out, "");
    EXPECT_FALSE(fs::exists(out_dir)) << out_dir << " was created";
  }

  const TempDir scratch_{"ballagg-test-cli-"};
  const fs::path& dir_ = scratch_.path();
};

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

int line_count(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

}  // namespace

// ---------------------------------------------------------------------------------------
// Commands that succeed

TEST_F(Cli, HelpExitsZeroAndListsTheCommands) {
  const Outcome o = run({"--help"});
  EXPECT_EQ(o.status, 0);
  EXPECT_CONTAINS(o.out, "run");
  EXPECT_CONTAINS(o.out, "config");
  EXPECT_EQ(o.err, "");
}

TEST_F(Cli, RunHelpExitsZeroAndListsItsOptions) {
  const Outcome o = run({"run", "--help"});
  EXPECT_EQ(o.status, 0);
  EXPECT_CONTAINS(o.out, "--out");
  EXPECT_CONTAINS(o.out, "--seed");
  EXPECT_CONTAINS(o.out, "--set");
}

TEST_F(Cli, VersionExitsZeroAndPrintsTheVersion) {
  const Outcome o = run({"--version"});
  EXPECT_EQ(o.status, 0);
  EXPECT_EQ(o.out.rfind("ballagg ", 0), 0u) << o.out;
  EXPECT_EQ(line_count(o.out), 1);
}

TEST_F(Cli, MissingCommandIsBadInput) {
  expect_bad_input({}, path("never"), {"subcommand"});
}

TEST_F(Cli, TinyRunWritesEveryResultFile) {
  const fs::path out = path("run");
  const Outcome o = tiny_run(out);
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(o.err, "");  // --quiet
  EXPECT_CONTAINS(o.out, out.string());
  for (const char* name : {"summary.json", "timeseries.csv", "final.csv", "final.xyz", "config.toml"})
    EXPECT_TRUE(fs::is_regular_file(out / name)) << name;
  // No temporary files are left behind.
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_NE(e.path().filename().string().front(), '.') << e.path();

  const nlohmann::json summary = read_json(out / "summary.json");
  EXPECT_EQ(summary["n_particles"], 16);
  EXPECT_EQ(summary["dimension"], 2);
  EXPECT_EQ(summary["n_clusters"], 1);  // default stop.clusters = 1
  EXPECT_EQ(summary["stop_reason"], "clusters");
  EXPECT_EQ(summary["seed"], 1);
  EXPECT_EQ(summary["config"]["system"]["n"], 16);

  const std::string csv = slurp(out / "final.csv");
  EXPECT_EQ(csv.rfind("x,y,vx,vy,radius,mass,cluster\n", 0), 0u);
  EXPECT_EQ(line_count(csv), 17);
  const std::string xyz = slurp(out / "final.xyz");
  EXPECT_EQ(xyz.rfind("16\n", 0), 0u) << xyz.substr(0, 40);
  EXPECT_GE(line_count(slurp(out / "timeseries.csv")), 3);  // header, t = 0, final
}

TEST_F(Cli, RunWithoutXyzWritesNoXyzFile) {
  const fs::path out = path("run");
  ASSERT_EQ(tiny_run(out, {"--set", "output.xyz=false"}).status, 0);
  EXPECT_TRUE(fs::exists(out / "final.csv"));
  EXPECT_FALSE(fs::exists(out / "final.xyz"));
}

TEST_F(Cli, RunIn3DWithPeriodicBoundaryWorks) {
  const fs::path out = path("run3");
  const Outcome o = tiny_run(out, {"--set", "system.dimension=3", "--set", "system.boundary=periodic", "--set",
                                   "initial.positions=random", "--set", "stop.clusters=4"});
  ASSERT_EQ(o.status, 0) << o.err;
  const nlohmann::json summary = read_json(out / "summary.json");
  EXPECT_EQ(summary["dimension"], 3);
  EXPECT_EQ(summary["boundary"], "periodic");
  EXPECT_LE(summary["n_clusters"].get<int>(), 4);
  EXPECT_EQ(slurp(out / "final.csv").rfind("x,y,z,vx,vy,vz,radius,mass,cluster\n", 0), 0u);
}

TEST_F(Cli, ExistingEmptyOutputDirectoryIsUsed) {
  const fs::path out = path("existing");
  fs::create_directories(out);
  ASSERT_EQ(tiny_run(out).status, 0);
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

TEST_F(Cli, MissingParentsOfTheOutputDirectoryAreCreated) {
  const fs::path out = path("a/b/c");
  ASSERT_EQ(tiny_run(out).status, 0);
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

TEST_F(Cli, ConfigFileAndSetOverridesAreBothApplied) {
  write(path("cfg.toml"), "[system]\nn = 9\nradius = 0.3\n[stop]\nclusters = 3\n");
  const fs::path out = path("run");
  const Outcome o = run({"run", "-q", path("cfg.toml").string(), "--out", out.string(), "--set", "system.n=25"});
  ASSERT_EQ(o.status, 0) << o.err;
  const nlohmann::json summary = read_json(out / "summary.json");
  EXPECT_EQ(summary["n_particles"], 25);
  EXPECT_EQ(summary["config"]["system"]["radius"], 0.3);
  EXPECT_EQ(summary["config"]["stop"]["clusters"], 3);
  EXPECT_LE(summary["n_clusters"].get<int>(), 3);
}

TEST_F(Cli, FinalCsvFedBackAsInitialFileContinuesTheRun) {
  const fs::path first = path("first");
  ASSERT_EQ(tiny_run(first, {"--set", "stop.clusters=6", "--set", "initial.positions=random"}).status, 0);
  const nlohmann::json s1 = read_json(first / "summary.json");
  ASSERT_LE(s1["n_clusters"].get<int>(), 6);
  ASSERT_GT(s1["n_clusters"].get<int>(), 1);
  const double box = s1["box_length"].get<double>();

  const fs::path second = path("second");
  std::ostringstream box_text;
  box_text.precision(17);
  box_text << box;
  const Outcome o = run({"run", "-q", "--out", second.string(), "--set", "initial.positions=file", "--set",
                         "initial.file=" + (first / "final.csv").string(), "--set",
                         "system.box_length=" + box_text.str()});
  ASSERT_EQ(o.status, 0) << o.err;
  const nlohmann::json s2 = read_json(second / "summary.json");
  EXPECT_EQ(s2["n_particles"], 16);
  EXPECT_EQ(s2["box_length"].get<double>(), box);
  EXPECT_EQ(s2["n_clusters"], 1);
  EXPECT_EQ(s2["mass_total"], s1["mass_total"]);
  // The glued clusters of the file start as clusters: 16 spheres but at most 6 bodies.
  EXPECT_LE(s2["merges"].get<int>(), s1["n_clusters"].get<int>() - 1);
  // The resolved config records the file and reproduces the second run.
  const fs::path third = path("third");
  ASSERT_EQ(run({"run", "-q", (second / "config.toml").string(), "--out", third.string()}).status, 0);
  EXPECT_EQ(slurp(third / "final.csv"), slurp(second / "final.csv"));
}

TEST_F(Cli, SameSeedGivesByteIdenticalFinalCsv) {
  const std::vector<std::string> extra{"--seed", "7", "--set", "initial.positions=random", "--set",
                                       "initial.velocities=gaussian"};
  ASSERT_EQ(tiny_run(path("a"), extra).status, 0);
  ASSERT_EQ(tiny_run(path("b"), extra).status, 0);
  const std::string a = slurp(path("a/final.csv"));
  EXPECT_GT(a.size(), 100u);
  EXPECT_EQ(a, slurp(path("b/final.csv")));
  EXPECT_EQ(slurp(path("a/timeseries.csv")), slurp(path("b/timeseries.csv")));
}

TEST_F(Cli, DifferentSeedGivesDifferentFinalCsv) {
  ASSERT_EQ(tiny_run(path("a"), {"--seed", "7"}).status, 0);
  ASSERT_EQ(tiny_run(path("b"), {"--seed", "8"}).status, 0);
  EXPECT_NE(slurp(path("a/final.csv")), slurp(path("b/final.csv")));
  EXPECT_EQ(read_json(path("b/summary.json"))["seed"], 8);
}

TEST_F(Cli, SeedOptionOverridesTheConfigSeed) {
  ASSERT_EQ(tiny_run(path("a"), {"--seed", "11"}).status, 0);
  ASSERT_EQ(tiny_run(path("b"), {"--set", "initial.seed=11"}).status, 0);
  EXPECT_EQ(slurp(path("a/final.csv")), slurp(path("b/final.csv")));
  EXPECT_CONTAINS(slurp(path("a/config.toml")), "seed = 11");
}

TEST_F(Cli, ResolvedConfigTomlReproducesTheRun) {
  ASSERT_EQ(tiny_run(path("a"), {"--seed", "3", "--set", "collision.outcome=bounce", "--set", "stop.time=2"}).status,
            0);
  const Outcome o = run({"run", "-q", path("a/config.toml").string(), "--out", path("b").string()});
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(slurp(path("a/final.csv")), slurp(path("b/final.csv")));
  EXPECT_EQ(slurp(path("a/config.toml")), slurp(path("b/config.toml")));
}

TEST_F(Cli, ConfigCommandPrintsTomlThatCanBeFedBack) {
  const Outcome first = run({"config", "--set", "system.n=49", "--set", "engine.kind=ed-naive"});
  ASSERT_EQ(first.status, 0) << first.err;
  EXPECT_CONTAINS(first.out, "[system]");
  EXPECT_CONTAINS(first.out, "n = 49");
  EXPECT_CONTAINS(first.out, "kind = \"ed-naive\"");
  write(path("printed.toml"), first.out);

  const Outcome again = run({"config", path("printed.toml").string()});
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(again.out, first.out);

  const Outcome ran = run({"run", "-q", path("printed.toml").string(), "--out", path("r").string()});
  ASSERT_EQ(ran.status, 0) << ran.err;
  EXPECT_EQ(read_json(path("r/summary.json"))["n_particles"], 49);
  EXPECT_EQ(read_json(path("r/summary.json"))["engine"], "ed-naive");
}

TEST_F(Cli, TimeSteppingRunWritesItsCountersAndItsResolvedConfig) {
  const Outcome o = run({"run", "-q", "--set", "engine.kind=ts", "--set", "system.n=400", "--set", "ts.dt_factor=0.01",
                         "--out", path("ts").string()});
  ASSERT_EQ(o.status, 0) << o.err;
  const auto j = read_json(path("ts/summary.json"));
  EXPECT_EQ(j["engine"], "ts");
  EXPECT_EQ(j["n_clusters"], 1);
  EXPECT_GT(j["steps"].get<int>(), 0);
  EXPECT_EQ(j["events"], j["steps"]);
  EXPECT_GT(j["minimisations"].get<int>(), 0);
  EXPECT_GT(j["daha_iterations"].get<int>(), 0);
  EXPECT_LE(j["max_residual_overlap"].get<double>(), 1e-3);
  EXPECT_LE(j["max_overlap"].get<double>(), 1e-3);
  EXPECT_FALSE(j.contains("list_rebuilds"));
  EXPECT_EQ(j["config"]["ts"]["model"], "rigid");
  EXPECT_DOUBLE_EQ(j["config"]["ts"]["delta_w"].get<double>(), 0.8);  // 4 R
  EXPECT_CONTAINS(slurp(path("ts/config.toml")), "[ts]");
}

TEST_F(Cli, BadTsValueIsOneLineAndExitStatus2) {
  const Outcome o = run({"run", "-q", "--set", "engine.kind=ts", "--set", "ts.eps_c=2", "--out", path("bad").string()});
  EXPECT_EQ(o.status, 2);
  EXPECT_EQ(line_count(o.err), 1);
  EXPECT_CONTAINS(o.err, "--set ts.eps_c: ts.eps_c = 2: must be a number in (0, 1)");
  EXPECT_FALSE(std::filesystem::exists(path("bad")));
}

TEST_F(Cli, ConfigCommandReportsBadInputLikeRun) {
  const Outcome o = run({"config", "--set", "system.n=zero"});
  EXPECT_EQ(o.status, 2);
  EXPECT_EQ(line_count(o.err), 1);
  EXPECT_CONTAINS(o.err, "--set system.n");
  EXPECT_EQ(o.out, "");
}

// ---------------------------------------------------------------------------------------
// Bad input: status 2, one line naming the key or the file line, no output directory

TEST_F(Cli, UnknownKeyInConfigFileNamesKeyAndLine) {
  write(path("cfg.toml"), "[system]\nn = 16\nradiuss = 0.3\n");
  expect_bad_input({"run", path("cfg.toml").string(), "--out", path("out").string()}, path("out"),
                   {path("cfg.toml").string() + ":3", "system.radiuss", "radius"});
}

TEST_F(Cli, UnknownKeyInSetIsBadInput) {
  expect_bad_input({"run", "--set", "stop.clusterz=3", "--out", path("out").string()}, path("out"),
                   {"--set stop.clusterz", "clusters"});
}

TEST_F(Cli, UnknownSectionIsBadInput) {
  write(path("cfg.toml"), "# c\n\n[sytem]\nn = 16\n");
  expect_bad_input({"run", path("cfg.toml").string(), "--out", path("out").string()}, path("out"),
                   {path("cfg.toml").string() + ":3", "[sytem]"});
}

TEST_F(Cli, BadValueNamesKeyAndWhatIsAllowed) {
  expect_bad_input({"run", "--set", "system.n=0", "--out", path("out").string()}, path("out"),
                   {"system.n", "from 1 to"});
  write(path("cfg.toml"), "[collision]\nrestitution = 1.5\n");
  expect_bad_input({"run", path("cfg.toml").string(), "--out", path("out").string()}, path("out"),
                   {path("cfg.toml").string() + ":2", "collision.restitution", "[0, 1]"});
}

TEST_F(Cli, WrongTypeNamesKeyAndLine) {
  write(path("cfg.toml"), "[output]\n\nxyz = \"no\"\n");
  expect_bad_input({"run", path("cfg.toml").string(), "--out", path("out").string()}, path("out"),
                   {path("cfg.toml").string() + ":3", "output.xyz", "true or false"});
}

TEST_F(Cli, NonFiniteValueIsBadInput) {
  expect_bad_input({"run", "--set", "system.radius=nan", "--out", path("out").string()}, path("out"),
                   {"system.radius"});
  write(path("cfg.toml"), "[initial]\nspeed = inf\n");
  expect_bad_input({"run", path("cfg.toml").string(), "--out", path("out").string()}, path("out"),
                   {path("cfg.toml").string() + ":2", "initial.speed"});
}

TEST_F(Cli, InvalidTomlSyntaxNamesTheLine) {
  write(path("cfg.toml"), "[system]\nn = 16\nradius = [\n");
  expect_bad_input({"run", path("cfg.toml").string(), "--out", path("out").string()}, path("out"),
                   {path("cfg.toml").string() + ":", "invalid TOML"});
}

TEST_F(Cli, MalformedSetIsBadInput) {
  expect_bad_input({"run", "--set", "n=16", "--out", path("out").string()}, path("out"),
                   {"--set n=16", "section.key=value"});
  expect_bad_input({"run", "--set", "system.n", "--out", path("out").string()}, path("out"),
                   {"--set system.n", "section.key=value"});
}

TEST_F(Cli, ConflictingKeysAreBadInput) {
  expect_bad_input({"run", "--set", "system.box_length=20", "--set", "system.volume_fraction=0.1", "--out",
                    path("out").string()},
                   path("out"), {"system.volume_fraction", "system.box_length"});
  expect_bad_input({"run", "--set", "initial.positions=file", "--out", path("out").string()}, path("out"),
                   {"initial.file"});
}

TEST_F(Cli, ImpossibleLatticePackingIsBadInput) {
  expect_bad_input({"run", "--set", "system.volume_fraction=0.85", "--out", path("out").string()}, path("out"),
                   {"initial.positions = \"lattice\"", "system.volume_fraction"});
}

TEST_F(Cli, VolumeFractionAboveTheDensestPackingIsBadInput) {
  expect_bad_input({"run", "--set", "system.volume_fraction=0.95", "--out", path("out").string()}, path("out"),
                   {"system.volume_fraction = 0.95", "0.9069"});
  expect_bad_input({"run", "--set", "system.dimension=3", "--set", "system.volume_fraction=0.8", "--out",
                    path("out").string()},
                   path("out"), {"system.volume_fraction = 0.8", "0.7405"});
}

TEST_F(Cli, ImpossibleRandomPackingIsBadInput) {
  expect_bad_input({"run", "--set", "system.n=200", "--set", "initial.positions=random", "--set",
                    "system.volume_fraction=0.6", "--out", path("out").string()},
                   path("out"), {"initial.positions = \"random\"", "system.volume_fraction"});
}

TEST_F(Cli, InputCsvWithOverlappingSpheresNamesBothLines) {
  write(path("in.csv"),
        "x,y,vx,vy,radius,mass\n"
        "1,1,0.1,0,0.5,1\n"
        "5,5,0,0.1,0.5,1\n"
        "1.5,1.2,0,0,0.5,1\n");
  expect_bad_input({"run", "--set", "initial.positions=file", "--set", "initial.file=" + path("in.csv").string(),
                    "--set", "system.box_length=10", "--out", path("out").string()},
                   path("out"), {path("in.csv").string() + ":2", "line 4", "overlap"});
}

TEST_F(Cli, InputCsvGluedClusterWithDisagreeingVelocitiesNamesTheLine) {
  write(path("in.csv"),
        "x,y,vx,vy,radius,mass,cluster\n"
        "# a glued pair\n"
        "1,1,0.1,0,0.5,1,0\n"
        "2,1,0.1,0.2,0.5,1,0\n"
        "5,5,0,0.1,0.5,1,1\n");
  expect_bad_input({"run", "--set", "initial.positions=file", "--set", "initial.file=" + path("in.csv").string(),
                    "--set", "system.box_length=10", "--out", path("out").string()},
                   path("out"), {path("in.csv").string() + ":4", path("in.csv").string() + ":3", "glued"});
}

TEST_F(Cli, InputCsvWithTwoIdenticalRowsInOneClusterNamesBothLines) {
  // Glued spheres never collide, but they overlap all the same: verify would report it.
  write(path("in.csv"),
        "x,y,vx,vy,radius,mass,cluster\n"
        "1,1,0.1,0,0.5,1,0\n"
        "5,5,0,0.1,0.5,1,1\n"
        "1,1,0.1,0,0.5,1,0\n");
  expect_bad_input({"run", "--set", "initial.positions=file", "--set", "initial.file=" + path("in.csv").string(),
                    "--set", "system.box_length=10", "--out", path("out").string()},
                   path("out"), {path("in.csv").string() + ":2", "line 4", "same cluster", "overlap"});
}

TEST_F(Cli, InputCsvClusterWhoseSpheresDoNotTouchNamesBothLines) {
  for (const std::string engine : {"ed", "rigid-body", "ts"}) {
    write(path("in.csv"),
          "x,y,z,vx,vy,vz,radius,mass,cluster\n"
          "1,1,1,0.1,0,0,0.5,1,7\n"
          "2,1,1,0.1,0,0,0.5,1,7\n"
          "5,5,5,0,0,0,0.5,1,8\n"
          "4,1,1,0.1,0,0,0.5,1,7\n");
    expect_bad_input({"run", "--set", "system.dimension=3", "--set", "engine.kind=" + engine, "--set",
                      "initial.positions=file", "--set", "initial.file=" + path("in.csv").string(), "--set",
                      "system.box_length=10", "--set", "stop.time=1", "--out", path("out").string()},
                     path("out"), {path("in.csv").string() + ":5", "line 2", "cluster 7", "touch"});
  }
}

TEST_F(Cli, InputCsvWithABadFieldNamesTheLine) {
  write(path("in.csv"), "x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1\n3,3,0,zero,0.5,1\n");
  expect_bad_input({"run", "--set", "initial.positions=file", "--set", "initial.file=" + path("in.csv").string(),
                    "--set", "system.box_length=10", "--out", path("out").string()},
                   path("out"), {path("in.csv").string() + ":3", "column vy"});
}

TEST_F(Cli, InputCsvWithZColumnIn2DIsBadInput) {
  write(path("in.csv"), "x,y,z,vx,vy,vz,radius,mass\n1,1,1,0,0,0,0.5,1\n");
  expect_bad_input({"run", "--set", "initial.positions=file", "--set", "initial.file=" + path("in.csv").string(),
                    "--set", "system.box_length=10", "--out", path("out").string()},
                   path("out"), {path("in.csv").string() + ":1", "'z'"});
}

TEST_F(Cli, InputCsvOutsideTheWallsIsBadInput) {
  write(path("in.csv"), "x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1\n9.8,3,0,0,0.5,1\n");
  expect_bad_input({"run", "--set", "initial.positions=file", "--set", "initial.file=" + path("in.csv").string(),
                    "--set", "system.box_length=10", "--out", path("out").string()},
                   path("out"), {path("in.csv").string() + ":3", "does not fit"});
}

TEST_F(Cli, UnreadableInputFileIsBadInput) {
  const std::string missing = path("missing.csv").string();
  expect_bad_input({"run", "--set", "initial.positions=file", "--set", "initial.file=" + missing, "--set",
                    "system.box_length=10", "--out", path("out").string()},
                   path("out"), {missing, "cannot read"});
  fs::create_directories(path("a_directory"));
  expect_bad_input({"run", "--set", "initial.positions=file", "--set", "initial.file=" + path("a_directory").string(),
                    "--set", "system.box_length=10", "--out", path("out").string()},
                   path("out"), {path("a_directory").string(), "cannot read"});
}

TEST_F(Cli, UnreadableConfigFileIsBadInput) {
  const std::string missing = path("missing.toml").string();
  expect_bad_input({"run", missing, "--out", path("out").string()}, path("out"), {missing, "cannot read"});
  fs::create_directories(path("a_directory"));
  expect_bad_input({"run", path("a_directory").string(), "--out", path("out").string()}, path("out"),
                   {path("a_directory").string(), "cannot read"});
}

TEST_F(Cli, UnknownCommandLineOptionIsBadInput) {
  expect_bad_input({"run", "--bogus", "--out", path("out").string()}, path("out"), {"--bogus"});
  expect_bad_input({"frobnicate", "--out", path("out").string()}, path("out"),
                   {"unknown command 'frobnicate' (commands: run, config, analyze, sweep, plot, render, verify;"});
}

TEST_F(Cli, BadSeedIsBadInput) {
  expect_bad_input({"run", "--seed", "seven", "--out", path("out").string()}, path("out"), {"--seed"});
  expect_bad_input({"run", "--seed", "-1", "--out", path("out").string()}, path("out"), {"--seed"});
  // Seeds beyond int64 could not be written back to config.toml.
  expect_bad_input({"run", "--seed", "18446744073709551615", "--out", path("out").string()}, path("out"),
                   {"--seed"});
}

TEST_F(Cli, OutputBelowARegularFileIsBadInput) {
  // Permission bits do not stop root, but nothing can create a directory below a file.
  write(path("plain"), "not a directory\n");
  const fs::path out = path("plain") / "sub";
  expect_bad_input({"run", "--set", "system.n=16", "--out", out.string()}, out, {"--out " + out.string()});
  EXPECT_EQ(slurp(path("plain")), "not a directory\n");
}

TEST_F(Cli, OutputThatIsAnExistingRegularFileIsBadInput) {
  write(path("plain"), "keep me\n");
  const Outcome o = run({"run", "--set", "system.n=16", "--out", path("plain").string()});
  EXPECT_EQ(o.status, 2);
  EXPECT_EQ(line_count(o.err), 1) << o.err;
  EXPECT_CONTAINS(o.err, "--out " + path("plain").string());
  EXPECT_CONTAINS(o.err, "not a directory");
  EXPECT_TRUE(fs::is_regular_file(path("plain")));
  EXPECT_EQ(slurp(path("plain")), "keep me\n");
}

TEST_F(Cli, BadInputCreatesNoParentDirectoriesEither) {
  const fs::path out = path("deep") / "er" / "out";
  expect_bad_input({"run", "--set", "system.n=-3", "--out", out.string()}, out, {"system.n"});
  EXPECT_FALSE(fs::exists(path("deep")));
}

// ---------------------------------------------------------------------------------------
// The bad-input catalogue (docs/hardening.md): what a new user tries. The
// wrong types, NaN and negative values of every key are in test_config.cpp; here what is
// left, through the binary.

TEST_F(Cli, NoSpheresIsBadInputNamingTheAllowedRange) {
  expect_bad_input({"run", "--set", "system.n=0", "--out", path("out").string()}, path("out"),
                   {"system.n", "from 1"});
}

TEST_F(Cli, OneSphereIsAlreadyASingleCluster) {
  const Outcome o = tiny_run(path("out"), {"--set", "system.n=1"});
  ASSERT_EQ(o.status, 0) << o.err;
  const nlohmann::json s = read_json(path("out") / "summary.json");
  EXPECT_EQ(s["n_clusters"], 1) << s.dump();
  EXPECT_EQ(s["collisions"], 0) << s.dump();
}

TEST_F(Cli, BoxSmallerThanASphereIsBadInput) {
  // Diameter 0.4 in a box of 0.3: neither start fits.
  expect_bad_input({"run", "--set", "system.n=1", "--set", "system.box_length=0.3", "--out", path("out").string()},
                   path("out"), {"diameter 0.4", "enlarge the box"});
  expect_bad_input({"run", "--set", "system.n=1", "--set", "system.box_length=0.3", "--set", "system.boundary=periodic",
                    "--out", path("out").string()},
                   path("out"), {"spacing 0.3", "diameter 0.4", "enlarge the box"});
}

TEST_F(Cli, EmptyTruncatedAndDuplicateColumnCsvNameTheFileLine) {
  auto from_file = [&](const std::string& name) {
    return std::vector<std::string>{"run", "--set", "initial.positions=\"file\"", "--set",
                                    "initial.file=\"" + path(name).string() + "\"", "--set", "system.box_length=10",
                                    "--out", path("out").string()};
  };
  write(path("empty.csv"), "");
  expect_bad_input(from_file("empty.csv"), path("out"), {path("empty.csv").string(), "empty file"});
  // A file cut short by a full disk or a killed writer: its last row ends mid-number.
  write(path("cut.csv"), "x,y,vx,vy,radius,mass\n1,1,0,0,0.2,1\n3,3,0,0,0.");
  expect_bad_input(from_file("cut.csv"), path("out"), {path("cut.csv").string() + ":3", "5 fields, but the header has 6"});
  write(path("cut2.csv"), "x,y,vx,vy,radius,mass\n1,1,0,0,0.2,1\n3,3,0,0,0.2,");
  expect_bad_input(from_file("cut2.csv"), path("out"), {path("cut2.csv").string() + ":3", "mass", "not a number"});
  write(path("twice.csv"), "x,y,vx,vy,radius,mass,x\n1,1,0,0,0.2,1,1\n");
  expect_bad_input(from_file("twice.csv"), path("out"), {path("twice.csv").string() + ":1", "'x' appears twice"});
}

TEST_F(Cli, OutputDirectoryThatCannotBeWrittenIsBadInput) {
  // Nothing, root included, can create a directory in /proc.
  const fs::path proc_out = "/proc/ballagg-hardening-test/out";
  expect_bad_input({"run", "--set", "system.n=16", "--out", proc_out.string()}, proc_out,
                   {"--out " + proc_out.string(), "cannot create the output directory"});
  if (::geteuid() == 0) return;  // permission bits do not stop root
  fs::create_directory(path("locked"));
  fs::permissions(path("locked"), fs::perms::owner_read | fs::perms::owner_exec);
  expect_bad_input({"run", "--set", "system.n=16", "--out", path("locked").string()}, path("locked") / "none",
                   {"--out " + path("locked").string(), "cannot write"});
  fs::permissions(path("locked"), fs::perms::owner_all);
}

namespace {

// A write that fails half-way (a full disk, a file-size limit) is the user's to mend like
// bad input: status 2, one line naming the file and the reason, and no file in the output
// directory half-written (nor its temporary). Files completed before it stay whole.
void expect_output_failure(const Outcome& o, const fs::path& out, const std::vector<std::string>& listing,
                           const std::string& reason) {
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_EQ(line_count(o.err), 1) << o.err;
  EXPECT_EQ(o.err.rfind("ballagg: error: " + out.string() + "/", 0), 0u) << o.err;
  EXPECT_CONTAINS(o.err, ": cannot write: " + reason);
  for (const std::string& name : listing)
    EXPECT_TRUE(name != "final.csv" && name.find(".tmp") == std::string::npos) << "left behind: " << name;
}

}  // namespace

TEST_F(Cli, FullDiskIsOneLineNamingTheFileAndLeavesNoPartialFile) {
  // A file-size limit of 16 KiB: a write beyond it fails with EFBIG, as on a full disk
  // (ENOSPC, NoSpaceLeftOnATinyFilesystem... below). final.csv of 400 discs is about 40 KB.
  // With SIGXFSZ ignored by the shell, and without: ballagg ignores it itself rather than
  // be ended by it with its temporary files left behind.
  for (const std::string trap : {"trap \"\" XFSZ; ", ""}) {
    SCOPED_TRACE(trap);
    const fs::path out = path(trap.empty() ? "out-signal" : "out");
    const std::string limited = "bash -c '" + trap + "ulimit -f 16; exec \"$0\" \"$@\"'";
    const Outcome o = ballagg::testing::run_ballagg(
        {"run", "--quiet", "--set", "system.n=400", "--out", out.string()}, dir_, limited);
    std::vector<std::string> listing;
    if (fs::exists(out))
      for (const fs::directory_entry& e : fs::directory_iterator(out)) {
        listing.push_back(e.path().filename().string());
        if (listing.back() == "timeseries.csv" || listing.back() == "config.toml") {
          EXPECT_GT(fs::file_size(e.path()), 0u) << listing.back();
        }
      }
    expect_output_failure(o, out, listing, "File too large");
    EXPECT_CONTAINS(o.err, (out / "final.csv").string());
  }
}

TEST_F(Cli, TrajectoryBeyondAFileSizeLimitIsOneLineNamingItAndLeavesNoPartialFile) {
  // The trajectory grows frame by frame on the background writer's thread: its failure
  // must still end the run with the same one line (the XYZ and the H5MD writer).
  const std::string limited = "bash -c 'trap \"\" XFSZ; ulimit -f 16; exec \"$0\" \"$@\"'";
  for (const std::string format : {"xyz", "h5md"}) {
    const fs::path out = path("out-" + format);
    // HDF5 1.10 loses a buffer of its own when a write fails (8200 bytes from H5FL_blk_malloc
    // in H5D__write): under `make sanitize` this run is checked for memory errors, not leaks.
    const std::string launcher =
        format == "h5md" ? "env ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" " + limited : limited;
    const Outcome o = ballagg::testing::run_ballagg({"run", "--quiet", "--set", "system.n=200", "--set",
                                                     "output.snapshot_every=0.05", "--set",
                                                     "output.snapshot_formats=\"" + format + "\"", "--out", out.string()},
                                                    dir_, launcher);
    std::vector<std::string> listing;
    if (fs::exists(out))
      for (const fs::directory_entry& e : fs::directory_iterator(out)) listing.push_back(e.path().filename().string());
    expect_output_failure(o, out, listing, "");
    EXPECT_CONTAINS(o.err, (out / ("trajectory." + format)).string());
    EXPECT_TRUE(std::find(listing.begin(), listing.end(), "trajectory." + format) == listing.end()) << format;
  }
}

TEST_F(Cli, NoSpaceLeftOnATinyFilesystemIsOneLineAndLeavesNoPartialFile) {
  // A 16 KiB tmpfs, mounted in a mount namespace of the run's own (unshare: no trace on the
  // machine, and no root needed where user namespaces are allowed). What the run left
  // there is listed from inside the namespace, before the mount disappears with it.
  const fs::path disk = path("disk"), out = disk / "out";
  fs::create_directory(disk);
  const std::string inside = "mount -t tmpfs -o size=16k tmpfs " + quoted(disk.string()) + " || exit 77; \"$0\" \"$@\"; " +
                             "s=$?; ls -A " + quoted(out.string()) + " > " + quoted(path("listing").string()) + "; exit $s";
  const Outcome o = ballagg::testing::run_ballagg(
      {"run", "--quiet", "--set", "system.n=400", "--out", out.string()}, dir_,
      "unshare --user --map-root-user --mount sh -c " + quoted(inside));
  if (o.status == 77 || !fs::exists(path("listing"))) GTEST_SKIP() << "cannot mount a tmpfs in a user namespace here";
  std::vector<std::string> listing;
  std::istringstream names(slurp(path("listing")));
  for (std::string name; std::getline(names, name);) listing.push_back(name);
  expect_output_failure(o, out, listing, "No space left on device");
}
