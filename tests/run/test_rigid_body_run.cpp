// Whole runs of the rigid-body engine through run_simulation: output files, the spin
// columns of final.csv read back, determinism, the test models' special coagulation, the
// energy threshold, fragmentation, the stop criteria.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ballagg/config/config.hpp"
#include "ballagg/engines/rigid_body/rigid_bodies.hpp"
#include "ballagg/engines/rigid_body/rigid_body_engine.hpp"
#include "ballagg/io/state_csv.hpp"
#include "ballagg/run/analyze_run.hpp"
#include "file_text.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::TempDir;

constexpr const char* kRigid = "[engine]\nkind = \"rigid-body\"\n";

using testing::slurp;

Config small_run(int dimension, const std::string& extra = "") {
  return parse_config_text(std::string(kRigid) + fmt::format(R"(
[system]
dimension = {}
n = 120
volume_fraction = 0.05
radius = 0.5
boundary = "periodic"
[initial]
positions = "random"
velocities = "gaussian"
[output]
xyz = false
)", dimension) + extra, "small.toml");
}

nlohmann::json summary_of(const std::filesystem::path& dir) { return nlohmann::json::parse(slurp(dir / "summary.json")); }
nlohmann::json analysis_of(const std::filesystem::path& dir) { return nlohmann::json::parse(slurp(dir / "analysis.json")); }

constexpr const char* kAnalysisFiles[] = {"analysis.json", "clusters.csv", "mass_spectrum.csv", "box_counting.csv",
                                          "pair_distribution.csv", "mass_radius.csv"};

TEST(RigidBodyRun, WritesTheRigidBodyColumnsAndFilesAndIsDeterministic) {
  TempDir dir;
  const Config c = small_run(3, "[stop]\ntime = 20\n");
  run_simulation(c, {(dir / "a").string(), true, false});
  run_simulation(c, {(dir / "b").string(), true, false});
  for (const char* f : {"final.csv", "timeseries.csv", "config.toml", "clusters.csv", "mass_spectrum.csv"})
    EXPECT_EQ(slurp(dir / "a" / f), slurp(dir / "b" / f)) << f;
  const std::string final_csv = slurp(dir / "a" / "final.csv");
  EXPECT_EQ(final_csv.substr(0, final_csv.find('\n')), "x,y,z,vx,vy,vz,radius,mass,cluster,wx,wy,wz");
  const std::string series = slurp(dir / "a" / "timeseries.csv");
  EXPECT_CONTAINS(series.substr(0, series.find('\n')), "first_time_collisions,max_mass,sigma_vx,sigma_vy,sigma_vz,rotational_energy,lx,ly,lz");
  const nlohmann::json j = summary_of(dir / "a");
  EXPECT_EQ(j["engine"], "rigid-body");
  EXPECT_GT(j["collisions"].get<int>(), 50);
  EXPECT_LE(j["first_time_collisions"].get<int>(), j["collisions"].get<int>());
  EXPECT_GT(j["rotational_energy_final"].get<double>(), 0.0);
  EXPECT_LT(j["max_overlap"].get<double>(), 1e-9);
  EXPECT_EQ(j["config"]["engine"]["skin"].get<double>(), rigid_body_skin(make_initial_state<3>(c)));
}

TEST(RigidBodyRun, EndStatisticsAreThoseOfBallaggAnalyzeAndAddUpToTheRunTotals) {
  // The run writes the files of `ballagg analyze` from its final state; the command run
  // afterwards on the directory gives the same bytes, and the clusters' kinetic energies
  // (translation, and rotation from the spin columns and the inertia tensor of eq. 1) add
  // up to the totals the engine kept.
  TempDir dir;
  run_simulation(small_run(3, "[stop]\ntime = 20\n"), {(dir / "run").string(), true, false});
  analyze_run({(dir / "run").string(), "", "", (dir / "again").string()});
  for (const char* f : kAnalysisFiles) EXPECT_EQ(slurp(dir / "run" / f), slurp(dir / "again" / f)) << f;
  const nlohmann::json s = summary_of(dir / "run"), a = analysis_of(dir / "run");
  EXPECT_EQ(a["n_clusters"], s["n_clusters"]);
  EXPECT_NEAR(a["translational_energy"].get<double>(), s["kinetic_energy_final"].get<double>(),
              1e-12 * s["kinetic_energy_final"].get<double>());
  EXPECT_NEAR(a["rotational_energy"].get<double>(), s["rotational_energy_final"].get<double>(),
              1e-12 * s["rotational_energy_final"].get<double>());
  const nlohmann::json& p = a["population"];
  EXPECT_GT(p["clusters_used"].get<int>(), 3);
  const double gamma = p["density_vs_size"]["slope"];
  EXPECT_DOUBLE_EQ(p["dimension_from_density"].get<double>(), 3.0 / (1.0 - gamma));  // eq. (32)
  EXPECT_GT(p["r_max_vs_size"]["slope"].get<double>(), 0.0);
  const std::string clusters = slurp(dir / "run" / "clusters.csv");
  EXPECT_CONTAINS(clusters.substr(0, clusters.find('\n')),
                  "velocity_x,velocity_y,velocity_z,omega_x,omega_y,omega_z,spin,translational_energy,rotational_energy");
}

TEST(RigidBodyRun, FinalStateWithSpinsReadsBackAndContinues) {
  TempDir dir;
  run_simulation(small_run(2, "[stop]\ntime = 15\n"), {(dir / "first").string(), true, false});
  const SphereTable<2> table = read_state_csv<2>((dir / "first" / "final.csv").string());
  ASSERT_EQ(table.spin.size(), table.radius.size());
  double spin = 0.0;
  for (const Spin<2>& w : table.spin) spin = std::max(spin, std::abs(w[0]));
  EXPECT_GT(spin, 0.0);
  const State<2> back = assemble_state(Box<2>{summary_of(dir / "first")["box_length"].get<double>(), Boundary::periodic}, table);
  ASSERT_EQ(back.spin.size(), back.clusters.size());
  EXPECT_EQ(back.n_clusters(), summary_of(dir / "first")["n_clusters"].get<int>());
  // The same file starts a new rigid-body run, but not an engine that cannot rotate.
  Config next = small_run(2, "[stop]\ntime = 5\n");
  next.initial.positions = InitialPositions::file;
  next.initial.file = (dir / "first" / "final.csv").string();
  next.system.box_length = back.box.length;
  next.system.volume_fraction.reset();
  run_simulation(next, {(dir / "second").string(), true, false});
  EXPECT_LT(summary_of(dir / "second")["max_overlap"].get<double>(), 1e-9);
  Config ed = next;
  ed.engine.kind = EngineKind::ed;
  try {
    make_initial_state<2>(ed);
    ADD_FAILURE() << "an ed run accepted spinning clusters";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "engine.kind = \"ed\" does not rotate clusters");
  }
}

TEST(RigidBodyRun, EnergyCreatingCoefficientsStopTheRunWithAClearErrorAndNoOutput) {
  TempDir dir;
  const Config c = small_run(3, "[collision]\noutcome = \"bounce\"\nmu_p = 8\n[stop]\ntime = 50\n");
  try {
    run_simulation(c, {(dir / "out").string(), true, false});
    ADD_FAILURE() << "the run accepted coefficients that create energy";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "collision.mu_t = 0, collision.mu_p = 8");
    EXPECT_CONTAINS(e.what(), "must not create energy");
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(RigidBodyRun, FrictionOpposingTheSlipDissipatesAndConservesMomentum) {
  // Equal spheres: with eps_n = 0.5, mu_t = 0.2 dissipates energy whatever the slip
  // (mu_t <= sqrt((1 - eps) / (1 + eps) 2 / 7) = 0.31, docs/rigid_body.md).
  TempDir dir;
  run_simulation(small_run(3, "[collision]\noutcome = \"bounce\"\nrestitution = 0.5\nmu_t = 0.2\ntc_time = 0\n[stop]\ntime = 10\n"),
                 {(dir / "friction").string(), true, false});
  run_simulation(small_run(3, "[collision]\noutcome = \"bounce\"\n[stop]\ntime = 10\n"), {(dir / "smooth").string(), true, false});
  auto energy = [&](const char* d, const char* when) {
    const nlohmann::json j = summary_of(dir / d);
    return j[std::string("kinetic_energy_") + when].get<double>() + j[std::string("rotational_energy_") + when].get<double>();
  };
  EXPECT_NEAR(energy("smooth", "final"), energy("smooth", "initial"), 1e-9 * energy("smooth", "initial"));
  EXPECT_LT(energy("friction", "final"), 0.5 * energy("friction", "initial"));
  EXPECT_GT(summary_of(dir / "friction")["rotational_energy_final"].get<double>(), 0.0);  // friction spins the spheres
  const nlohmann::json j = summary_of(dir / "friction");
  EXPECT_GT(j["bounces"].get<int>(), 50);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(j["momentum_final"][a].get<double>(), j["momentum_initial"][a].get<double>(), 1e-10);
}

TEST(RigidBodyRun, EnergyThresholdSticksSlowImpactsAndBouncesFastOnes) {
  TempDir dir;
  run_simulation(small_run(3, "[collision]\noutcome = \"energy-threshold\"\n[stop]\ntime = 20\n"),
                 {(dir / "out").string(), true, false});
  const nlohmann::json j = summary_of(dir / "out");
  const int collisions = j["collisions"], bounces = j["bounces"], merges = j["merges"];
  EXPECT_GT(bounces, 10);
  EXPECT_GT(merges, 10);
  EXPECT_EQ(bounces + merges, collisions);
  // The default threshold is the initial mean kinetic energy per body.
  const Config c = small_run(3, "[collision]\noutcome = \"energy-threshold\"\n");
  const State<3> s = make_initial_state<3>(c);
  EXPECT_DOUBLE_EQ(j["config"]["collision"]["energy_threshold"].get<double>(), s.kinetic_energy() / s.n_clusters());
  EXPECT_LT(j["config"]["collision"]["tc_time"].get<double>(), 1e-6);
}

TEST(RigidBodyRun, BridgesLawDissipatesMoreAtHigherSpeed) {
  TempDir dir;
  const std::string law = "[collision]\noutcome = \"bounce\"\nrestitution_law = \"bridges\"\nvelocity_unit = ";
  run_simulation(small_run(3, law + "0.01\n[stop]\ntime = 10\n"), {(dir / "slow").string(), true, false});
  run_simulation(small_run(3, law + "100\n[stop]\ntime = 10\n"), {(dir / "fast").string(), true, false});
  auto loss = [&](const char* d) {
    const nlohmann::json j = summary_of(dir / d);
    return 1.0 - (j["kinetic_energy_final"].get<double>() + j["rotational_energy_final"].get<double>()) /
                     j["kinetic_energy_initial"].get<double>();
  };
  EXPECT_GT(loss("fast"), loss("slow"));
  EXPECT_GT(loss("slow"), 0.0);
}

TEST(RigidBodyRun, SphereCoagulationAtConstantDensityGrowsTheRadius) {
  TempDir dir;
  run_simulation(small_run(3, "[collision]\ncoagulation = \"sphere\"\n[stop]\ntime = 30\n"), {(dir / "out").string(), true, false});
  const SphereTable<3> t = read_state_csv<3>((dir / "out" / "final.csv").string());
  const nlohmann::json j = summary_of(dir / "out");
  EXPECT_EQ(static_cast<int>(t.radius.size()), j["n_clusters"].get<int>());  // every body is one sphere
  EXPECT_LT(j["n_clusters"].get<int>(), 100);
  double mass = 0.0;
  for (std::size_t k = 0; k < t.radius.size(); ++k) {
    EXPECT_NEAR(t.radius[k], 0.5 * std::cbrt(t.mass[k]), 1e-12);  // R^3 proportional to m
    mass += t.mass[k];
  }
  EXPECT_NEAR(mass, 120.0, 1e-9);
  EXPECT_LT(j["max_overlap"].get<double>(), 1e-9);
}

TEST(RigidBodyRun, FragmentationBreaksAggregatesAndConservesMomentum) {
  TempDir dir;
  run_simulation(small_run(3, "[collision]\nfragmentation_energy = 0.8\n[stop]\ntime = 30\n"), {(dir / "out").string(), true, false});
  const nlohmann::json j = summary_of(dir / "out");
  EXPECT_GT(j["fragmentations"].get<int>(), 0);
  const auto p0 = j["momentum_initial"], p1 = j["momentum_final"];
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(p1[a].get<double>(), p0[a].get<double>(), 1e-10);
  EXPECT_LT(j["max_overlap"].get<double>(), 1e-9);
}

// summary.json states the collision law from the resolved configuration: the impact
// energy's formula, the thresholds with their derivation, the Bridges law's units; and a
// run of the written config.toml writes the same files.
TEST(RigidBodyRun, SummaryStatesTheCollisionLawAsTheResolvedConfigGivesIt) {
  TempDir dir;
  const std::string law = "[collision]\noutcome = \"energy-threshold\"\nrestitution_law = \"bridges\"\n"
                          "velocity_unit = 0.01\nfragmentation = \"initial-energy\"\nfragmentation_factor = 2\n"
                          "[stop]\ntime = 15\n";
  run_simulation(small_run(3, law), {(dir / "out").string(), true, false});
  const nlohmann::json j = summary_of(dir / "out");
  const State<3> s = make_initial_state<3>(small_run(3, law));
  const double mean = mean_kinetic_energy_per_body(s);
  const nlohmann::json& k = j["collision_law"];
  const nlohmann::json& cfg = j["config"]["collision"];
  EXPECT_EQ(k["outcome"], "energy-threshold");
  EXPECT_EQ(k["coagulation"], "aggregate");
  EXPECT_EQ(k["impact_energy"]["formula"], "1/2 mu |V_1 - V_2|^2, mu = m_1 m_2 / (m_1 + m_2)");
  EXPECT_CONTAINS(k["impact_energy"]["velocities"].get<std::string>(), "centre-of-mass velocities");
  EXPECT_EQ(k["energy_threshold"]["energy"].get<double>(), mean);
  EXPECT_EQ(k["energy_threshold"]["energy"], cfg["energy_threshold"]);
  EXPECT_EQ(k["energy_threshold"]["factor"].get<double>(), 1.0);
  EXPECT_CONTAINS(k["energy_threshold"]["derivation"].get<std::string>(), "collision.energy_threshold_factor x the initial mean kinetic energy per body");
  EXPECT_EQ(k["fragmentation"]["mode"], "initial-energy");
  EXPECT_EQ(k["fragmentation"]["energy"].get<double>(), 2.0 * mean);
  EXPECT_EQ(k["fragmentation"]["energy"], cfg["fragmentation_energy"]);
  EXPECT_EQ(k["fragmentation"]["factor"].get<double>(), 2.0);
  EXPECT_EQ(k["restitution"]["law"], "bridges");
  EXPECT_EQ(k["restitution"]["critical_speed_cm_per_s"].get<double>(), 0.0077);
  EXPECT_EQ(k["restitution"]["exponent"].get<double>(), -0.234);
  EXPECT_EQ(k["restitution"]["velocity_unit_cm_per_s"], cfg["velocity_unit"]);
  EXPECT_DOUBLE_EQ(k["restitution"]["critical_speed"].get<double>(), 0.77);
  EXPECT_GT(j["fragmentations"].get<int>(), 0);
  EXPECT_GT(j["bounces"].get<int>(), 0);

  run_simulation(load_config((dir / "out" / "config.toml").string(), {}), {(dir / "again").string(), true, false});
  nlohmann::json again = summary_of(dir / "again"), first = j;
  for (nlohmann::json* x : {&again, &first}) x->erase("wall_seconds"), x->erase("events_per_second");
  EXPECT_EQ(again, first);
  for (const char* file : {"final.csv", "config.toml", "timeseries.csv"}) EXPECT_EQ(slurp(dir / "again" / file), slurp(dir / "out" / file)) << file;
}

TEST(RigidBodyRun, SummaryOfAGivenThresholdAndNoFragmentationSaysSo) {
  TempDir dir;
  run_simulation(small_run(2, "[collision]\noutcome = \"energy-threshold\"\nenergy_threshold = 0.7\nrestitution = 0.5\n"
                              "[stop]\ntime = 5\n"), {(dir / "out").string(), true, false});
  const nlohmann::json k = summary_of(dir / "out")["collision_law"];
  EXPECT_EQ(k["energy_threshold"]["energy"].get<double>(), 0.7);
  EXPECT_TRUE(k["energy_threshold"]["factor"].is_null());
  EXPECT_EQ(k["energy_threshold"]["derivation"], "collision.energy_threshold, given as an energy");
  EXPECT_EQ(k["restitution"], nlohmann::json::parse(R"({"law": "constant", "eps_n": 0.5, "mu_t": 0.0})"));
  EXPECT_EQ(k["fragmentation"], nlohmann::json::parse(R"({"mode": "off"})"));
}

TEST(RigidBodyRun, StopsWhenTheAggregatedFractionIsReached) {
  TempDir dir;
  run_simulation(small_run(3, "[stop]\naggregated_fraction = 0.5\n"), {(dir / "out").string(), true, false});
  const nlohmann::json j = summary_of(dir / "out");
  EXPECT_EQ(j["stop_reason"], "aggregated");
  const double fraction = analysis_of(dir / "out")["aggregated_mass_fraction"];
  EXPECT_GE(fraction, 0.5);
  EXPECT_LT(fraction, 0.5 + 4.0 / 120);  // stopped at the merge that crossed it
}

TEST(RigidBodyRun, StopsWhenABodySpansThePeriodicBox) {
  TempDir dir;
  Config c = small_run(3);
  c.system.volume_fraction = 0.15;
  run_simulation(c, {(dir / "out").string(), true, false});
  const nlohmann::json j = summary_of(dir / "out");
  EXPECT_EQ(j["stop_reason"], "body_spans_box");
  EXPECT_LT(j["max_overlap"].get<double>(), 1e-9);
}

}  // namespace
}  // namespace ballagg

namespace ballagg {
namespace {

// examples/richardson1995/model-*.toml load, and each runs shrunk (200 spheres in a box of
// the same density, a tenth of the time) without overlaps.
TEST(RigidBodyExamples, RichardsonModelsLoadAndRunShrunk) {
  int seen = 0;
  for (const char* model : {"i", "ii", "iii", "iv", "v"}) {
    SCOPED_TRACE(model);
    Config c = load_config(std::string(BALLAGG_SOURCE_DIR) + "/examples/richardson1995/model-" + model + ".toml", {});
    EXPECT_EQ(c.engine.kind, EngineKind::rigid_body);
    EXPECT_EQ(c.system.dimension, 3);
    const double density = c.system.n / std::pow(*c.system.box_length, 3);
    c.system.n = 200;
    c.system.box_length = std::cbrt(200 / density);
    c.stop.time /= 10;
    State<3> s = make_initial_state<3>(c);
    const Config resolved = resolve_defaults(c, s);
    RunObserver<3> none;
    const RunResult r = make_engine<3>(resolved)->run(s, stop_criteria(resolved), none);
    EXPECT_EQ(r.reason, StopReason::time);
    EXPECT_GT(r.counters.collisions, 10);
    EXPECT_LT(testing::worst_overlap(s), 1e-9);
    ++seen;
  }
  EXPECT_EQ(seen, 5);
}

}  // namespace
}  // namespace ballagg
