// The rigid-body engine's configuration keys: every key read, every bad value or bad
// combination rejected with the key named (its whole runs: tests/run/test_rigid_body_run.cpp).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ballagg/config/config.hpp"
#include "ballagg/config/rigid_body_section.hpp"
#include "ballagg/engines/rigid_body/rigid_body_engine.hpp"
#include "ballagg/io/state_csv.hpp"
#include "ballagg/run/analyze_run.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

using testing::TempDir;

std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse_config_text(text, "run.toml", overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected InputError for:\n" << text;
  return {};
}

constexpr const char* kRigid = "[engine]\nkind = \"rigid-body\"\n";

TEST(RigidBodyConfig, EveryKeyIsRead) {
  const Config c = parse_config_text(std::string(kRigid) + R"(
[system]
dimension = 3
[initial]
velocities = "fixed-speed"
[collision]
outcome = "energy-threshold"
coagulation = "aggregate"
restitution_law = "bridges"
velocity_unit = 0.01
mu_t = 0.2
mu_p = -0.1
energy_threshold = 3.5
fragmentation_energy = 40
[stop]
aggregated_fraction = 0.99
)", "every.toml");
  EXPECT_EQ(c.engine.kind, EngineKind::rigid_body);
  EXPECT_EQ(c.collision.outcome, CollisionOutcome::energy_threshold);
  EXPECT_EQ(c.rigid_body.coagulation, Coagulation::aggregate);
  EXPECT_EQ(c.rigid_body.restitution_law, RestitutionLaw::bridges);
  EXPECT_EQ(c.rigid_body.velocity_unit, 0.01);
  EXPECT_EQ(c.rigid_body.mu_t, 0.2);
  EXPECT_EQ(c.rigid_body.mu_p, -0.1);
  EXPECT_EQ(c.rigid_body.energy_threshold, 3.5);
  EXPECT_EQ(c.rigid_body.fragmentation_energy, 40.0);
  EXPECT_EQ(c.stop.aggregated_fraction, 0.99);
  const Config sphere = parse_config_text(std::string(kRigid) +
                                              "[collision]\ncoagulation = \"sphere\"\nmerged_radius = \"fixed\"\n"
                                              "constant_speed = true\n",
                                          "t");
  EXPECT_EQ(sphere.rigid_body.coagulation, Coagulation::sphere);
  EXPECT_EQ(sphere.rigid_body.merged_radius, MergedRadius::fixed);
  EXPECT_TRUE(sphere.rigid_body.constant_speed);
}

TEST(RigidBodyConfig, ResolvedConfigReadsBackToTheSameKeys) {
  const Config c = parse_config_text(std::string(kRigid) +
                                         "[system]\ndimension = 3\n[collision]\noutcome = \"energy-threshold\"\n"
                                         "restitution_law = \"bridges\"\nvelocity_unit = 0.5\nmu_t = 0.1\n"
                                         "energy_threshold = 2\n[stop]\naggregated_fraction = 0.5\n",
                                     "t");
  const std::string text = to_toml_text(c);
  EXPECT_CONTAINS(text, "kind = \"rigid-body\"");
  EXPECT_CONTAINS(text, "coagulation = \"aggregate\"");
  EXPECT_EQ(text.find("restitution = "), std::string::npos);  // the Bridges law replaces it
  const Config again = parse_config_text(text, "resolved.toml");
  EXPECT_EQ(to_toml_text(again), text);
  EXPECT_EQ(again.rigid_body.velocity_unit, 0.5);
  EXPECT_EQ(again.stop.aggregated_fraction, 0.5);
}

TEST(RigidBodyConfig, EdConfigTextIsUnchangedByTheRigidBodyKeys) {
  const std::string text = to_toml_text(parse_config_text("", "t"));
  EXPECT_EQ(text.find("coagulation"), std::string::npos);
  EXPECT_EQ(text.find("mu_t"), std::string::npos);
}

TEST(RigidBodyConfig, BadValuesNameTheKeyAndWhatIsAllowed) {
  const std::string r = kRigid;
  EXPECT_CONTAINS(error_of(r + "[collision]\noutcome = \"glue\"\n"), "run.toml:4: collision.outcome = \"glue\": must be one of \"stick\", \"bounce\", \"energy-threshold\"");
  EXPECT_CONTAINS(error_of(r + "[collision]\ncoagulation = \"blob\"\n"), "collision.coagulation = \"blob\": must be one of \"aggregate\", \"sphere\"");
  EXPECT_CONTAINS(error_of(r + "[collision]\ncoagulation = \"sphere\"\nmerged_radius = \"big\"\n"), "collision.merged_radius");
  EXPECT_CONTAINS(error_of(r + "[collision]\nrestitution_law = \"ice\"\n"), "collision.restitution_law");
  EXPECT_CONTAINS(error_of(r + "[collision]\nrestitution_law = \"bridges\"\nvelocity_unit = 0\n"), "collision.velocity_unit = 0: must be a number > 0");
  EXPECT_CONTAINS(error_of(r + "[collision]\nmu_t = -0.1\n"), "collision.mu_t = -0.1: must be a number in [0, 10]");
  EXPECT_CONTAINS(error_of(r + "[system]\ndimension = 3\n[collision]\nmu_p = 11\n"), "collision.mu_p = 11");
  EXPECT_CONTAINS(error_of(r + "[collision]\noutcome = \"energy-threshold\"\nenergy_threshold = -1\n"), "collision.energy_threshold = -1: must be a number > 0");
  EXPECT_CONTAINS(error_of(r + "[collision]\nfragmentation_energy = nan\n"), "collision.fragmentation_energy");
  EXPECT_CONTAINS(error_of(r + "[stop]\naggregated_fraction = 1.5\n"), "stop.aggregated_fraction = 1.5: must be a number in (0, 1]");
  EXPECT_CONTAINS(error_of(r + "[collision]\nconstant_speed = 1\n"), "collision.constant_speed = 1: must be true or false");
  EXPECT_CONTAINS(error_of(r, {"collision.mu_t=x"}), "--set collision.mu_t");
}

TEST(RigidBodyConfig, ImpossibleCombinationsAreRejected) {
  const std::string r = kRigid;
  EXPECT_CONTAINS(error_of("[collision]\nmu_t = 0.1\n"), "collision.mu_t is a key of the rigid-body engine: it needs engine.kind = \"rigid-body\"");
  EXPECT_CONTAINS(error_of("[collision]\noutcome = \"energy-threshold\"\n"), "needs engine.kind = \"rigid-body\"");
  EXPECT_CONTAINS(error_of("[stop]\naggregated_fraction = 0.5\n"), "stop.aggregated_fraction needs engine.kind = \"rigid-body\"");
  EXPECT_CONTAINS(error_of("[engine]\nkind = \"ts\"\n[collision]\ncoagulation = \"sphere\"\n"), "collision.coagulation");
  EXPECT_CONTAINS(error_of(r + "[collision]\nenergy_threshold = 1\n"), "only used with collision.outcome = \"energy-threshold\"");
  EXPECT_CONTAINS(error_of(r + "[collision]\nmerged_radius = \"fixed\"\n"), "collision.merged_radius is only used with collision.coagulation = \"sphere\"");
  EXPECT_CONTAINS(error_of(r + "[collision]\ncoagulation = \"sphere\"\nfragmentation_energy = 1\n"), "it needs collision.coagulation = \"aggregate\"");
  EXPECT_CONTAINS(error_of(r + "[initial]\nvelocities = \"gaussian\"\n[collision]\ncoagulation = \"sphere\"\nconstant_speed = true\n"),
                  "it needs initial.velocities = \"fixed-speed\"");
  EXPECT_CONTAINS(error_of(r + "[collision]\nrestitution = 0.5\nrestitution_law = \"bridges\"\n"), "not both");
  EXPECT_CONTAINS(error_of(r + "[collision]\nvelocity_unit = 2\n"), "only used with collision.restitution_law = \"bridges\"");
  EXPECT_CONTAINS(error_of(r + "[collision]\nmu_p = 0.1\n"), "in 2D the contact has one tangent");
}

TEST(RigidBodyConfig, FragmentationKeysAreReadAndTheirCombinationsChecked) {
  const std::string r = kRigid;
  const Config paper = parse_config_text(r + "[collision]\nfragmentation = \"initial-energy\"\nfragmentation_factor = 3\n", "t");
  EXPECT_EQ(paper.rigid_body.fragmentation, Fragmentation::initial_energy);
  EXPECT_EQ(paper.rigid_body.fragmentation_factor, 3.0);
  EXPECT_FALSE(paper.rigid_body.fragmentation_energy);  // resolved by the run
  const Config absolute = parse_config_text(r + "[collision]\nfragmentation_energy = 40\n", "t");
  EXPECT_EQ(absolute.rigid_body.fragmentation, Fragmentation::energy);  // an energy alone means "energy"
  EXPECT_EQ(parse_config_text(r, "t").rigid_body.fragmentation, Fragmentation::off);
  // Each collision section with what its one-line error must say.
  const std::pair<std::string, std::string> refused[] = {
      {"fragmentation = \"sometimes\"\n",
       "collision.fragmentation = \"sometimes\": must be one of \"off\", \"initial-energy\", \"energy\""},
      {"fragmentation = \"initial-energy\"\nfragmentation_factor = 0\n",
       "collision.fragmentation_factor = 0: must be a number > 0"},
      {"fragmentation = \"off\"\nfragmentation_energy = 1\n",
       "collision.fragmentation = \"off\" with collision.fragmentation_energy"},
      {"fragmentation = \"energy\"\n",
       "collision.fragmentation = \"energy\" needs collision.fragmentation_energy"},
      {"fragmentation_factor = 2\n",
       "collision.fragmentation_factor is only used with collision.fragmentation = \"initial-energy\""},
      {"coagulation = \"sphere\"\nfragmentation = \"initial-energy\"\n",
       "collision.fragmentation breaks aggregates up: it needs collision.coagulation = \"aggregate\""},
      {"energy_threshold_factor = 2\n",
       "collision.energy_threshold_factor is only used with collision.outcome = \"energy-threshold\""},
      {"outcome = \"energy-threshold\"\nenergy_threshold_factor = -1\n",
       "collision.energy_threshold_factor = -1: must be a number > 0"},
  };
  for (const auto& [section, message] : refused) EXPECT_CONTAINS(error_of(r + "[collision]\n" + section), message);
  EXPECT_CONTAINS(error_of(r, {"collision.fragmentation=energy"}), "--set collision.fragmentation=energy");
}

// The thresholds derived from the initial mean kinetic energy per body (here 2.5): the
// defaults (factor 1 each), other factors, energies given as such, and the resolved text,
// which reads back and resolves again to the same bytes.
TEST(RigidBodyConfig, ThresholdsDefaultToMultiplesOfTheInitialMeanEnergyPerBody) {
  const std::string r = std::string(kRigid) + "[collision]\noutcome = \"energy-threshold\"\n";
  Config c = parse_config_text(r + "fragmentation = \"initial-energy\"\n", "t");
  resolve_rigid_body_energies(c, 2.5);
  EXPECT_EQ(c.rigid_body.energy_threshold, 2.5);
  EXPECT_EQ(c.rigid_body.energy_threshold_factor, kDefaultEnergyThresholdFactor);
  EXPECT_EQ(c.rigid_body.fragmentation_energy, 2.5);
  EXPECT_EQ(c.rigid_body.fragmentation_factor, kDefaultFragmentationFactor);
  EXPECT_EQ(kDefaultEnergyThresholdFactor, 1.0);  // the paper's §3
  EXPECT_EQ(kDefaultFragmentationFactor, 1.0);    // §2.6 names no other multiple
  const std::string text = to_toml_text(c);
  EXPECT_CONTAINS(text, "energy_threshold = 2.5\nenergy_threshold_factor = 1.0\nfragmentation = \"initial-energy\"\n"
                        "fragmentation_factor = 1.0\nfragmentation_energy = 2.5\n");
  Config again = parse_config_text(text, "config.toml");
  resolve_rigid_body_energies(again, 2.5);
  EXPECT_EQ(to_toml_text(again), text);

  Config scaled = parse_config_text(r + "energy_threshold_factor = 0.5\nfragmentation = \"initial-energy\"\n"
                                        "fragmentation_factor = 4\n", "t");
  resolve_rigid_body_energies(scaled, 2.5);
  EXPECT_EQ(scaled.rigid_body.energy_threshold, 1.25);
  EXPECT_EQ(scaled.rigid_body.fragmentation_energy, 10.0);

  Config given = parse_config_text(r + "energy_threshold = 7\nfragmentation_energy = 9\n", "t");
  resolve_rigid_body_energies(given, 2.5);
  EXPECT_EQ(given.rigid_body.energy_threshold, 7.0);
  EXPECT_FALSE(given.rigid_body.energy_threshold_factor);  // given as an energy: no factor written
  EXPECT_EQ(given.rigid_body.fragmentation_energy, 9.0);
  EXPECT_FALSE(given.rigid_body.fragmentation_factor);
  EXPECT_EQ(to_toml_text(given).find("_factor"), std::string::npos);

  Config stick = parse_config_text(std::string(kRigid), "t");
  resolve_rigid_body_energies(stick, 2.5);
  EXPECT_FALSE(stick.rigid_body.energy_threshold);
  EXPECT_FALSE(stick.rigid_body.fragmentation_energy);
}

TEST(RigidBodyConfig, AnEnergyBesideItsFactorMustBeThatMultiple) {
  const std::string r = std::string(kRigid) + "[collision]\noutcome = \"energy-threshold\"\n";
  auto resolve_error = [](Config c, double mean) -> std::string {
    try {
      resolve_rigid_body_energies(c, mean);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "expected InputError";
    return {};
  };
  // A resolved config.toml of another start (here: mean energy 3 instead of 2.5).
  EXPECT_CONTAINS(resolve_error(parse_config_text(r + "energy_threshold = 2.5\nenergy_threshold_factor = 1\n", "c.toml"), 3.0),
                  "c.toml: collision.energy_threshold = 2.5 is not collision.energy_threshold_factor = 1 times the initial "
                  "mean kinetic energy per body (3), which gives 3: give one of the two keys");
  EXPECT_CONTAINS(resolve_error(parse_config_text(r + "fragmentation = \"initial-energy\"\nfragmentation_factor = 2\n"
                                                      "fragmentation_energy = 5\n", "c.toml"), 3.0),
                  "collision.fragmentation_energy = 5 is not collision.fragmentation_factor = 2 times");
  // The mode derives the energy: one given beside it (without a factor) is checked against factor 1.
  EXPECT_CONTAINS(resolve_error(parse_config_text(r + "fragmentation = \"initial-energy\"\nfragmentation_energy = 5\n", "c.toml"), 3.0),
                  "collision.fragmentation_energy = 5 is not collision.fragmentation_factor = 1 times");
  EXPECT_CONTAINS(resolve_error(parse_config_text(r + "fragmentation = \"initial-energy\"\n", "c.toml"), 0.0),
                  "the bodies start at rest");
}

}  // namespace
}  // namespace ballagg
