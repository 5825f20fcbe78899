// `ballagg verify`: it passes on real runs of every engine and catches doctored files (an
// overlap, a cluster in two pieces, a wrong summary count, momentum from nowhere).
#include <algorithm>
#include <filesystem>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::Outcome;
using testing::slurp;
using testing::TempDir;

class Verify : public ::testing::Test {
 protected:
  Outcome ballagg(const std::vector<std::string>& args) { return testing::run_ballagg(args, tmp_.path()); }
  std::string run(const std::string& name, std::vector<std::string> sets) {
    const std::string out = (tmp_ / name).string();
    std::vector<std::string> args{"run", "--quiet", "--out", out};
    for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
    const Outcome o = ballagg(args);
    EXPECT_EQ(o.status, 0) << o.err;
    return out;
  }
  void expect_verified(const std::string& dir) {
    const Outcome o = ballagg({"verify", dir});
    EXPECT_EQ(o.status, 0) << o.out << o.err;
    EXPECT_CONTAINS(o.out, "checks hold");
  }
  // Violations: status 1, and a line starting with `what`.
  void expect_violation(const std::string& dir, const std::string& what) {
    const Outcome o = ballagg({"verify", dir});
    EXPECT_EQ(o.status, 1) << o.out << o.err;
    EXPECT_CONTAINS("\n" + o.out, "\n" + what);
  }
  TempDir tmp_;
};

// final.csv as rows of fields (header first).
std::vector<std::vector<std::string>> rows_of(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(slurp(path));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::istringstream s(line);
    for (std::string f; std::getline(s, f, ',');) row.push_back(f);
    rows.push_back(row);
  }
  return rows;
}
void write_rows(const std::string& path, const std::vector<std::vector<std::string>>& rows) {
  std::string text;
  for (const auto& r : rows) {
    for (std::size_t k = 0; k < r.size(); ++k) text += (k ? "," : "") + r[k];
    text += "\n";
  }
  testing::write(path, text);
}

TEST_F(Verify, PassesOnRunsOfEveryEngine) {
  expect_verified(run("ed2d", {"system.n=600"}));
  expect_verified(run("ed3d", {"system.dimension=3", "system.n=500", "system.boundary=\"periodic\""}));
  expect_verified(run("gas", {"system.n=400", "collision.outcome=\"bounce\"", "collision.restitution=0.7", "stop.time=5"}));
  expect_verified(run("naive", {"system.n=80", "engine.kind=\"ed-naive\""}));
  expect_verified(run("ts", {"system.n=400", "engine.kind=\"ts\""}));
  expect_verified(run("ts-almost", {"system.n=150", "engine.kind=\"ts\"", "ts.model=\"almost-rigid\"", "stop.clusters=40"}));
}

// ts.method = "paper" takes a minimisation that never met (3.28) as it is: its run leaves
// overlaps beyond eps_c and reports them; verify accepts what the run reports, with a note,
// and still catches an overlap beyond it.
TEST_F(Verify, AcceptsTheOverlapsThePaperMethodReports) {
  const std::string dir = run("paper", {"system.n=100", "engine.kind=\"ts\"", "ts.method=\"paper\"",
                                        "ts.model=\"non-rigid\"", "ts.max_iterations=8", "stop.clusters=20"});
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir + "/summary.json"));
  ASSERT_GT(summary["minimisations_unconverged"].get<double>(), 0);
  ASSERT_GT(summary["max_overlap"].get<double>(), 1e-3);
  const Outcome o = ballagg({"verify", dir});
  EXPECT_EQ(o.status, 0) << o.out << o.err;
  EXPECT_CONTAINS(o.err, "ts.method = \"paper\" left overlaps up to");
  // Sphere 2 put on sphere 1, deeper than anything the run reports (radius 0.2).
  auto rows = rows_of(dir + "/final.csv");
  const double deeper = 0.4 * (1.0 - summary["max_overlap"].get<double>()) / 2.0;
  rows[2][0] = fmt::format("{}", std::stod(rows[1][0]) + deeper);
  rows[2][1] = rows[1][1];
  write_rows(dir + "/final.csv", rows);
  expect_violation(dir, "overlap: ");
}

// Runs of drawn radii: the initial mass is the sum over the drawn spheres' masses, not
// n * system.mass; their box and analysis read back from config.toml.
TEST_F(Verify, PassesOnPolydisperseRuns) {
  expect_verified(run("lognormal", {"system.n=300", "system.radius_distribution=\"lognormal\"", "system.radius_sigma=1.5",
                                    "initial.positions=\"random\""}));
  expect_verified(run("discrete", {"system.dimension=3", "system.n=200", "system.radius_distribution=\"discrete\"",
                                   "system.radii=[0.1,0.3]", "system.density=2", "system.boundary=\"periodic\""}));
}

// Columns of final.csv in 2D: x, y, vx, vy, radius, mass, cluster.
TEST_F(Verify, CatchesAnOverlap) {
  const std::string dir = run("half", {"system.n=400", "stop.clusters=200"});
  auto rows = rows_of(dir + "/final.csv");
  // Sphere 2 put almost on top of sphere 1 (a different cluster or the same: an overlap).
  const double x = std::stod(rows[1][0]) + 0.01;
  rows[2][0] = fmt::format("{}", x);
  rows[2][1] = rows[1][1];
  write_rows(dir + "/final.csv", rows);
  expect_violation(dir, "overlap: 1 pair(s) overlap");
}

TEST_F(Verify, CatchesAClusterInTwoPieces) {
  const std::string dir = run("half", {"system.n=400", "stop.clusters=300"});
  auto rows = rows_of(dir + "/final.csv");
  // Two spheres alone in their clusters, far apart, given one label (and one velocity):
  // a cluster of two spheres that do not touch.
  std::map<std::string, int> size;
  for (std::size_t k = 1; k < rows.size(); ++k) ++size[rows[k][6]];
  std::vector<std::size_t> alone;
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (size[rows[k][6]] == 1) alone.push_back(k);
  ASSERT_GE(alone.size(), 2u);
  const std::size_t a = alone.front(), b = alone.back();
  rows[b][6] = rows[a][6];
  rows[b][2] = rows[a][2];
  rows[b][3] = rows[a][3];
  write_rows(dir + "/final.csv", rows);
  expect_violation(dir, "connected clusters: 1 cluster(s) whose spheres do not form one contact graph");
}

TEST_F(Verify, CatchesAWrongSummaryCount) {
  const std::string dir = run("run", {"system.n=300", "stop.clusters=100"});
  nlohmann::ordered_json summary = nlohmann::ordered_json::parse(slurp(dir + "/summary.json"));
  summary["n_clusters"] = summary["n_clusters"].get<int>() + 1;
  testing::write(dir + "/summary.json", summary.dump(2));
  expect_violation(dir, "summary: n_clusters = 101, final.csv has 100 clusters");
}

// Momentum from nowhere: a cluster's velocity changed in final.csv and in the summary's
// final momentum alike, so only the budget (initial + walls) can tell.
TEST_F(Verify, CatchesMomentumNotAccountedFor) {
  const std::string dir = run("run", {"system.n=300", "system.boundary=\"periodic\"", "stop.clusters=299"});
  auto rows = rows_of(dir + "/final.csv");
  nlohmann::ordered_json summary = nlohmann::ordered_json::parse(slurp(dir + "/summary.json"));
  std::map<std::string, int> size;
  for (std::size_t k = 1; k < rows.size(); ++k) ++size[rows[k][6]];
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (size[rows[k][6]] == 1) {
      const double vx = std::stod(rows[k][2]);
      rows[k][2] = fmt::format("{}", vx * 0.5);  // energy falls: only momentum is wrong
      summary["momentum_final"][0] = summary["momentum_final"][0].get<double>() - 0.5 * vx;
      summary["kinetic_energy_final"] = summary["kinetic_energy_final"].get<double>() - 0.375 * vx * vx;
      break;
    }
  write_rows(dir + "/final.csv", rows);
  testing::write(dir + "/summary.json", summary.dump(2));
  expect_violation(dir, "momentum budget: final - initial - wall impulse");
}

// ---- rigid bodies (rigid-body engine): spins, rotational energy, angular momentum ----

const std::vector<std::string> kRigid{"engine.kind=\"rigid-body\"", "initial.velocities=\"gaussian\""};
std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Rotating aggregates: a 3D gas of aggregates with walls stuck together to 40 bodies; then
// the same bodies, spinning, as the initial state of a run of elastic, frictionless
// bounces (eps_n = 1, mu = 0), whose total kinetic energy must be conserved though the
// translational part alone is not.
class VerifyRigid : public Verify {
 protected:
  std::string aggregates() {
    return run("aggregates", with(kRigid, {"system.dimension=3", "system.n=300", "system.volume_fraction=0.1", "stop.clusters=40"}));
  }
  std::string elastic() {
    const std::string from = aggregates();
    const auto box = nlohmann::json::parse(slurp(from + "/summary.json"))["box_length"].get<double>();
    return run("elastic", {"engine.kind=\"rigid-body\"", "system.dimension=3", fmt::format("system.box_length={}", box),
                           "initial.positions=\"file\"", fmt::format("initial.file=\"{}/final.csv\"", from),
                           "collision.outcome=\"bounce\"", "stop.time=3"});
  }
  // Multiplies every spin of final.csv (3D: columns wx, wy, wz) by f, and the summary's
  // rotational energy by f^2: the files agree, only a budget can tell.
  void scale_spins(const std::string& dir, double f) {
    auto rows = rows_of(dir + "/final.csv");
    for (std::size_t k = 1; k < rows.size(); ++k)
      for (int a = 9; a < 12; ++a) rows[k][a] = fmt::format("{}", f * std::stod(rows[k][a]));
    write_rows(dir + "/final.csv", rows);
    nlohmann::ordered_json summary = nlohmann::ordered_json::parse(slurp(dir + "/summary.json"));
    summary["rotational_energy_final"] = f * f * summary["rotational_energy_final"].get<double>();
    testing::write(dir + "/summary.json", summary.dump(2));
  }
};

TEST_F(VerifyRigid, PassesOnRigidBodyRuns) {
  expect_verified(run("walls2d", with(kRigid, {"system.n=400", "stop.clusters=60"})));
  expect_verified(run("model-v", with(kRigid, {"system.dimension=3", "system.n=1000", "system.box_length=10",
                                              "system.radius=0.033", "system.boundary=\"periodic\"", "initial.speed=10",
                                              "collision.outcome=\"energy-threshold\"", "collision.restitution_law=\"bridges\"",
                                              "collision.velocity_unit=0.01", "stop.time=4"})));
  expect_verified(run("model-i", {"engine.kind=\"rigid-body\"", "system.dimension=3", "system.n=500", "system.box_length=10",
                                  "system.radius=0.1", "system.boundary=\"periodic\"", "collision.coagulation=\"sphere\"",
                                  "collision.merged_radius=\"fixed\"", "collision.constant_speed=true", "stop.time=2"}));
  const std::string dir = elastic();
  expect_verified(dir);
  const auto summary = nlohmann::json::parse(slurp(dir + "/summary.json"));
  EXPECT_GT(summary["bounces"].get<int>(), 20);
  EXPECT_GT(summary["rotational_energy_initial"].get<double>(), 0.0);  // the bodies spin
}

TEST_F(VerifyRigid, CatchesASphereSpinningApartFromItsBody) {
  const std::string dir = aggregates();
  auto rows = rows_of(dir + "/final.csv");
  std::map<std::string, int> size;
  for (std::size_t k = 1; k < rows.size(); ++k) ++size[rows[k][8]];
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (size[rows[k][8]] > 1) {
      rows[k][11] = fmt::format("{}", std::stod(rows[k][11]) + 0.1);
      break;
    }
  write_rows(dir + "/final.csv", rows);
  expect_violation(dir, "rigid clusters: 1 cluster(s) whose spheres move with different velocities or spins");
}

TEST_F(VerifyRigid, CatchesRotationalEnergyFromNowhere) {
  const std::string dir = aggregates();
  scale_spins(dir, 30.0);
  expect_violation(dir, "energy budget: kinetic energy (translation and rotation) grew");
}

TEST_F(VerifyRigid, CatchesElasticBouncesThatLoseEnergy) {
  const std::string dir = elastic();
  scale_spins(dir, 0.99);
  expect_violation(dir, "energy budget: elastic, frictionless bounces");
}

TEST_F(VerifyRigid, CatchesAWrongAngularMomentum) {
  const std::string dir = aggregates();
  nlohmann::ordered_json summary = nlohmann::ordered_json::parse(slurp(dir + "/summary.json"));
  summary["angular_momentum_final"][2] = summary["angular_momentum_final"][2].get<double>() + 1.0;
  testing::write(dir + "/summary.json", summary.dump(2));
  expect_violation(dir, "angular momentum: angular_momentum_final");
}

TEST_F(Verify, NotARunDirectoryIsBadInput) {
  const Outcome o = ballagg({"verify", (tmp_ / "nothing").string()});
  EXPECT_EQ(o.status, 2);
  EXPECT_CONTAINS(o.err, "not a run directory");
}


// ---- Trajectories (docs/verify.md, "Trajectories") ----

namespace fs = std::filesystem;

// The frames of an extended-XYZ trajectory, each its lines.
std::vector<std::string> xyz_frames(const std::string& path) {
  std::vector<std::string> frames;
  std::istringstream in(slurp(path));
  for (std::string count; std::getline(in, count);) {
    std::string frame = count + "\n", line;
    for (int k = 0; k < std::stoi(count) + 1 && std::getline(in, line); ++k) frame += line + "\n";
    frames.push_back(frame);
  }
  return frames;
}

const std::vector<std::string> kTrajectories = {"output.snapshot_every=0.5", "output.snapshot_formats=[\"xyz\", \"h5md\"]"};

TEST_F(Verify, PassesOnTrajectoriesOfEveryEngine) {
  expect_verified(run("ed2d", with({"system.n=200"}, kTrajectories)));
  expect_verified(run("ed3d", with({"system.dimension=3", "system.n=150", "system.boundary=\"periodic\""}, kTrajectories)));
  expect_verified(run("gas", with({"system.n=100", "collision.outcome=\"bounce\"", "stop.time=3.2"}, kTrajectories)));
  expect_verified(run("ts", with({"system.n=150", "engine.kind=\"ts\""}, kTrajectories)));
  expect_verified(run("rigid", with({"system.n=60", "engine.kind=\"rigid-body\"", "stop.clusters=20"}, kTrajectories)));
  // A frame due at the final instant (stop.time a multiple of snapshot_every).
  expect_verified(run("on-time", with({"system.n=100", "collision.outcome=\"bounce\"", "stop.time=2"}, kTrajectories)));
}

TEST_F(Verify, CatchesARepeatedTrajectoryFrame) {
  // As two writers of one run directory left it: frames after a point written twice.
  const std::string dir = run("twice", {"system.n=100", "collision.outcome=\"bounce\"", "stop.time=3",
                                        "output.snapshot_every=0.5", "output.snapshot_formats=[\"xyz\"]"});
  const std::vector<std::string> frames = xyz_frames(dir + "/trajectory.xyz");
  ASSERT_EQ(frames.size(), 7u);
  std::string text;
  for (std::size_t k = 0; k < frames.size(); ++k) text += frames[k];
  for (std::size_t k = 4; k < frames.size(); ++k) text += frames[k];
  testing::write(dir + "/trajectory.xyz", text);
  expect_violation(dir, "trajectory.xyz: 1 frame(s) out of time order or repeated (frame 7 at t = 2 after frame 6 at t = 3)");
}

TEST_F(Verify, CatchesTrajectoryFramesOfAnotherRun) {
  // Frames of a run of another seed and schedule before this run's: a trajectory spliced
  // from two runs.
  const std::vector<std::string> gas{"system.n=100", "collision.outcome=\"bounce\"", "stop.time=3",
                                     "output.snapshot_formats=[\"xyz\"]"};
  const std::string dir = run("this", with(gas, {"output.snapshot_every=1"}));
  const std::string other = run("other", with(gas, {"output.snapshot_every=0.25", "initial.seed=9"}));
  const std::vector<std::string> mine = xyz_frames(dir + "/trajectory.xyz"), theirs = xyz_frames(other + "/trajectory.xyz");
  ASSERT_EQ(mine.size(), 4u);
  testing::write(dir + "/trajectory.xyz", theirs[0] + theirs[1] + theirs[2] + mine[3]);
  expect_violation(dir, "trajectory.xyz: 2 frame(s) not at the run's snapshot times (frame 1 at t = 0.25, where "
                        "output.snapshot_every = 1 puts it at t = 1)");
}

TEST_F(Verify, CatchesATrajectoryOfOtherSpheresOrAnotherBoxOrDimension) {
  const std::vector<std::string> sets{"system.n=100", "collision.outcome=\"bounce\"", "stop.time=2",
                                      "output.snapshot_every=0.5", "output.snapshot_formats=[\"xyz\", \"h5md\"]"};
  const std::string dir = run("this", sets);
  const std::string fewer = run("fewer", with(sets, {"system.n=90", "system.box_length=30"}));
  const std::string deep = run("deep", with(sets, {"system.dimension=3"}));
  fs::copy_file(fewer + "/trajectory.xyz", dir + "/trajectory.xyz", fs::copy_options::overwrite_existing);
  expect_violation(dir, "trajectory.xyz: 5 frame(s) with another number of spheres than the run's 100 (frame 0 has 90)");
  expect_violation(dir, "trajectory.xyz: 5 frame(s) in another box than the run's side");
  fs::copy_file(deep + "/trajectory.h5md", dir + "/trajectory.h5md", fs::copy_options::overwrite_existing);
  expect_violation(dir, "trajectory.h5md: ");
}

TEST_F(Verify, CatchesATrajectoryTheRunDoesNotWrite) {
  // The trajectory of an earlier run left beside a run that writes none.
  const std::string with_frames = run("frames", with({"system.n=100"}, kTrajectories));
  const std::string dir = run("none", {"system.n=100"});
  fs::copy_file(with_frames + "/trajectory.h5md", dir + "/trajectory.h5md");
  expect_violation(dir, "trajectory.h5md: config.toml writes no such trajectory");
}

}  // namespace
}  // namespace ballagg
