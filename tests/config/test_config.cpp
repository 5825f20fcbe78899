// The TOML configuration layer: defaults, every key, --set overrides, box length formulas,
// the resolved TOML round trip, and error messages that name the key and the file line.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/config/config.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using ballagg::Config;
using ballagg::InputError;
using ballagg::parse_config_text;
using ballagg::SnapshotFormat;
using ballagg::SnapshotPrecision;

using ballagg::testing::TempDir;

namespace {

// The message of the InputError thrown by parsing `text` (with overrides); fails the test
// if nothing (or something else) is thrown.
std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {},
                     const std::string& source = "run.toml") {
  try {
    parse_config_text(text, source, overrides);
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected InputError for:\n" << text;
  return {};
}

// Every field of two configs is equal (the source name is not compared).
void expect_same_config(const Config& a, const Config& b) {
  EXPECT_EQ(a.system.dimension, b.system.dimension);
  EXPECT_EQ(a.system.n, b.system.n);
  EXPECT_EQ(a.system.volume_fraction, b.system.volume_fraction);
  EXPECT_EQ(a.system.box_length, b.system.box_length);
  EXPECT_EQ(a.system.radius, b.system.radius);
  EXPECT_EQ(a.system.mass, b.system.mass);
  EXPECT_EQ(a.system.boundary, b.system.boundary);
  EXPECT_EQ(a.initial.positions, b.initial.positions);
  EXPECT_EQ(a.initial.velocities, b.initial.velocities);
  EXPECT_EQ(a.initial.speed, b.initial.speed);
  EXPECT_EQ(a.initial.lattice_spacing, b.initial.lattice_spacing);
  EXPECT_EQ(a.initial.file, b.initial.file);
  EXPECT_EQ(a.initial.zero_momentum, b.initial.zero_momentum);
  EXPECT_EQ(a.initial.seed, b.initial.seed);
  EXPECT_EQ(a.collision.outcome, b.collision.outcome);
  EXPECT_EQ(a.collision.restitution, b.collision.restitution);
  EXPECT_EQ(a.collision.tc_time, b.collision.tc_time);
  EXPECT_EQ(a.engine.kind, b.engine.kind);
  EXPECT_EQ(a.engine.skin, b.engine.skin);
  EXPECT_EQ(a.stop.clusters, b.stop.clusters);
  EXPECT_EQ(a.stop.time, b.stop.time);
  EXPECT_EQ(a.stop.wall_seconds, b.stop.wall_seconds);
  EXPECT_EQ(a.output.timeseries_interval, b.output.timeseries_interval);
  EXPECT_EQ(a.output.xyz, b.output.xyz);
  EXPECT_EQ(a.output.checkpoint_every, b.output.checkpoint_every);
}

// A file with every key set to a non-default value.
const char* const kEveryKey = R"(# every key, none at its default
[system]
dimension = 3
n = 1000
volume_fraction = 0.15
radius = 0.25
mass = 2.5
boundary = "periodic"

[initial]
positions = "random"
velocities = "gaussian"
speed = 3.5
zero_momentum = true
seed = 42

[collision]
outcome = "bounce"
restitution = 0.75
tc_time = 1e-6

[engine]
kind = "ed-naive"
skin = 0.125

[stop]
clusters = 10
time = 100.0
wall_seconds = 60

[output]
timeseries_interval = 0.5
xyz = false
checkpoint_every = 30
)";

}  // namespace

// ---------------------------------------------------------------------------------------
// Defaults and keys

TEST(Config, EmptyTextGivesTheDocumentedDefaults) {
  const Config c = parse_config_text("", "empty.toml");
  EXPECT_EQ(c.system.dimension, 2);
  EXPECT_EQ(c.system.n, 2500);
  ASSERT_TRUE(c.system.volume_fraction.has_value());
  EXPECT_EQ(*c.system.volume_fraction, 0.2);
  EXPECT_FALSE(c.system.box_length.has_value());
  EXPECT_EQ(c.system.radius, 0.2);
  EXPECT_EQ(c.system.mass, 1.0);
  EXPECT_EQ(c.system.boundary, ballagg::Boundary::walls);
  EXPECT_EQ(c.initial.positions, ballagg::InitialPositions::lattice);
  EXPECT_EQ(c.initial.velocities, ballagg::InitialVelocities::fixed_speed);
  EXPECT_EQ(c.initial.speed, 1.0);
  EXPECT_TRUE(c.initial.file.empty());
  EXPECT_FALSE(c.initial.zero_momentum);
  EXPECT_EQ(c.initial.seed, 1u);
  EXPECT_EQ(c.collision.outcome, ballagg::CollisionOutcome::stick);
  EXPECT_EQ(c.collision.restitution, 1.0);
  EXPECT_FALSE(c.collision.tc_time.has_value());
  EXPECT_EQ(c.engine.kind, ballagg::EngineKind::ed);
  EXPECT_FALSE(c.engine.skin.has_value());
  EXPECT_EQ(c.stop.clusters, 1);
  EXPECT_TRUE(std::isinf(c.stop.time) && c.stop.time > 0);
  EXPECT_TRUE(std::isinf(c.stop.wall_seconds) && c.stop.wall_seconds > 0);
  EXPECT_EQ(c.output.timeseries_interval, 0.0);
  EXPECT_TRUE(c.output.xyz);
  EXPECT_EQ(c.output.checkpoint_every, 300.0);  // wall seconds
  EXPECT_EQ(c.source, "empty.toml");
}

TEST(Config, LoadConfigWithoutFileGivesTheDefaults) {
  const Config c = ballagg::load_config("", {});
  expect_same_config(c, parse_config_text("", "x"));
  EXPECT_EQ(c.source, "(defaults)");
}

TEST(Config, EveryKeyIsRead) {
  const Config c = parse_config_text(kEveryKey, "every.toml");
  EXPECT_EQ(c.system.dimension, 3);
  EXPECT_EQ(c.system.n, 1000);
  EXPECT_EQ(c.system.volume_fraction, 0.15);
  EXPECT_FALSE(c.system.box_length.has_value());
  EXPECT_EQ(c.system.radius, 0.25);
  EXPECT_EQ(c.system.mass, 2.5);
  EXPECT_EQ(c.system.boundary, ballagg::Boundary::periodic);
  EXPECT_EQ(c.initial.positions, ballagg::InitialPositions::random);
  EXPECT_EQ(c.initial.velocities, ballagg::InitialVelocities::gaussian);
  EXPECT_EQ(c.initial.speed, 3.5);
  EXPECT_TRUE(c.initial.zero_momentum);
  EXPECT_EQ(c.initial.seed, 42u);
  EXPECT_EQ(c.collision.outcome, ballagg::CollisionOutcome::bounce);
  EXPECT_EQ(c.collision.restitution, 0.75);
  EXPECT_EQ(c.collision.tc_time, 1e-6);
  EXPECT_EQ(c.engine.kind, ballagg::EngineKind::ed_naive);
  EXPECT_EQ(c.engine.skin, 0.125);
  EXPECT_EQ(c.stop.clusters, 10);
  EXPECT_EQ(c.stop.time, 100.0);
  EXPECT_EQ(c.stop.wall_seconds, 60.0);  // an integer where a real is expected is accepted
  EXPECT_EQ(c.output.timeseries_interval, 0.5);
  EXPECT_FALSE(c.output.xyz);
  EXPECT_EQ(c.output.checkpoint_every, 30.0);
}

TEST(Config, EveryChoiceOfEveryEnumeratedKeyIsAccepted) {
  EXPECT_EQ(parse_config_text("[initial]\nvelocities = \"uniform\"", "t").initial.velocities,
            ballagg::InitialVelocities::uniform);
  EXPECT_EQ(parse_config_text("[initial]\nvelocities = \"fixed-speed\"", "t").initial.velocities,
            ballagg::InitialVelocities::fixed_speed);
  EXPECT_EQ(parse_config_text("[initial]\npositions = \"lattice\"", "t").initial.positions,
            ballagg::InitialPositions::lattice);
  EXPECT_EQ(parse_config_text("[system]\nboundary = \"walls\"", "t").system.boundary, ballagg::Boundary::walls);
  EXPECT_EQ(parse_config_text("[collision]\noutcome = \"stick\"", "t").collision.outcome,
            ballagg::CollisionOutcome::stick);
  EXPECT_EQ(parse_config_text("[engine]\nkind = \"ed\"", "t").engine.kind, ballagg::EngineKind::ed);
}

TEST(Config, FilePositionsNeedBoxLengthAndLeaveVolumeFractionUnset) {
  const Config c = parse_config_text(
      "[system]\nbox_length = 12.5\n[initial]\npositions = \"file\"\nfile = \"start.csv\"\n", "t");
  EXPECT_EQ(c.initial.positions, ballagg::InitialPositions::file);
  EXPECT_EQ(c.initial.file, "start.csv");
  EXPECT_EQ(c.system.box_length, 12.5);
  EXPECT_FALSE(c.system.volume_fraction.has_value());
  EXPECT_EQ(ballagg::resolved_box_length(c), 12.5);
}

TEST(Config, BoxLengthAloneLeavesVolumeFractionUnset) {
  const Config c = parse_config_text("[system]\nbox_length = 30\n", "t");
  EXPECT_EQ(c.system.box_length, 30.0);
  EXPECT_FALSE(c.system.volume_fraction.has_value());
  EXPECT_EQ(ballagg::resolved_box_length(c), 30.0);
}

TEST(Config, LatticeSpacingSetsTheBoxAndLeavesVolumeFractionUnset) {
  const Config c = parse_config_text("[system]\nn = 2500\n[initial]\nlattice_spacing = 1.0\n", "t");
  EXPECT_EQ(c.initial.lattice_spacing, 1.0);
  EXPECT_FALSE(c.system.volume_fraction.has_value());
  EXPECT_FALSE(c.system.box_length.has_value());
  EXPECT_EQ(ballagg::resolved_box_length(c), 50.0);  // 50 sites per side
  // 3D, 10 spheres: a 3 x 3 x 3 lattice.
  EXPECT_EQ(ballagg::resolved_box_length(parse_config_text(
                "[system]\ndimension = 3\nn = 10\nradius = 0.2\n[initial]\nlattice_spacing = 0.5\n", "t")),
            1.5);
  // The resolved configuration names it and reads back to the same configuration.
  const std::string text = ballagg::to_toml_text(c);
  EXPECT_CONTAINS(text, "lattice_spacing = 1.0\n");
  EXPECT_EQ(text.find("volume_fraction"), std::string::npos);
  expect_same_config(parse_config_text(text, "resolved"), c);
}

TEST(Config, LatticeSpacingIsRefusedWhereItCannotApply) {
  EXPECT_CONTAINS(error_of("[initial]\nlattice_spacing = 0\n"), "run.toml:2: initial.lattice_spacing = 0: must be a number > 0");
  EXPECT_CONTAINS(error_of("", {"initial.lattice_spacing=1e30"}),
                  "--set initial.lattice_spacing: initial.lattice_spacing = 1e+30: must be at most 1e+26");
  EXPECT_CONTAINS(error_of("[initial]\npositions = \"random\"\nlattice_spacing = 1.0\n"),
                  "run.toml:3: initial.lattice_spacing = 1: is read only with initial.positions = \"lattice\" (it is \"random\")");
  EXPECT_CONTAINS(error_of("[system]\nvolume_fraction = 0.1\n[initial]\nlattice_spacing = 1.0\n"),
                  "initial.lattice_spacing = 1: sets the box (L = sites per side x spacing): give it or "
                  "system.volume_fraction, not both");
  EXPECT_CONTAINS(error_of("[system]\nbox_length = 10\n[initial]\nlattice_spacing = 1.0\n"),
                  "give it or system.box_length, not both");
  EXPECT_CONTAINS(error_of("", {"initial.lattice_spacing=0.4"}),
                  "--set initial.lattice_spacing: initial.lattice_spacing = 0.4: must be larger than the diameter 2 "
                  "system.radius = 0.4");
  EXPECT_CONTAINS(error_of("[system]\nn = 100\nradius = 1e-6\n[initial]\nlattice_spacing = 1e2\n"),
                  "makes the box 10 x 100 = 1000 long, more than 1e+06 times the radius");
}

TEST(Config, StopTimeAndWallSecondsAcceptInfinity) {
  const Config c = parse_config_text("[stop]\ntime = inf\nwall_seconds = +inf\n", "t");
  EXPECT_TRUE(std::isinf(c.stop.time) && c.stop.time > 0);
  EXPECT_TRUE(std::isinf(c.stop.wall_seconds) && c.stop.wall_seconds > 0);
}

TEST(Config, ZeroIsAcceptedWhereTheRangeIsClosedAtZero) {
  const Config c = parse_config_text(
      "[initial]\nspeed = 0\nseed = 0\n[collision]\nrestitution = 0.0\ntc_time = 0.0\n[output]\ntimeseries_interval = 0\n",
      "t");
  EXPECT_EQ(c.initial.speed, 0.0);
  EXPECT_EQ(c.initial.seed, 0u);
  EXPECT_EQ(c.collision.restitution, 0.0);
  EXPECT_EQ(c.collision.tc_time, 0.0);
  EXPECT_EQ(c.output.timeseries_interval, 0.0);
}

// ---------------------------------------------------------------------------------------
// --set overrides

TEST(Config, SetOverridesNumbersStringsAndBooleans) {
  const Config c = parse_config_text(kEveryKey, "every.toml",
                                     {"system.n=400", "system.radius=0.5", "engine.kind=ed", "output.xyz=true",
                                      "initial.positions=lattice", "collision.restitution=1",
                                      "system.boundary=\"walls\""});
  EXPECT_EQ(c.system.n, 400);
  EXPECT_EQ(c.system.radius, 0.5);
  EXPECT_EQ(c.engine.kind, ballagg::EngineKind::ed);
  EXPECT_TRUE(c.output.xyz);
  EXPECT_EQ(c.initial.positions, ballagg::InitialPositions::lattice);
  EXPECT_EQ(c.collision.restitution, 1.0);
  EXPECT_EQ(c.system.boundary, ballagg::Boundary::walls);
  EXPECT_EQ(c.system.dimension, 3);  // keys not overridden keep the file's values
  EXPECT_EQ(c.initial.seed, 42u);
}

TEST(Config, SetAcceptsABareStringWithADash) {
  const Config c = parse_config_text("", "t", {"engine.kind=ed-naive", "initial.velocities=fixed-speed"});
  EXPECT_EQ(c.engine.kind, ballagg::EngineKind::ed_naive);
  EXPECT_EQ(c.initial.velocities, ballagg::InitialVelocities::fixed_speed);
}

TEST(Config, SetAcceptsExponentNotationForIntegers) {
  const Config c = parse_config_text("", "t", {"system.n=1e4", "stop.clusters=2e1", "initial.seed=1E3"});
  EXPECT_EQ(c.system.n, 10000);
  EXPECT_EQ(c.stop.clusters, 20);
  EXPECT_EQ(c.initial.seed, 1000u);
}

TEST(Config, SetCreatesAMissingSection) {
  const Config c = parse_config_text("[system]\nn = 9\n", "t", {"stop.clusters=3", "collision.outcome=bounce"});
  EXPECT_EQ(c.system.n, 9);
  EXPECT_EQ(c.stop.clusters, 3);
  EXPECT_EQ(c.collision.outcome, ballagg::CollisionOutcome::bounce);
}

TEST(Config, LaterSetOfTheSameKeyWins) {
  const Config c = parse_config_text("", "t", {"system.n=10", "system.n=20"});
  EXPECT_EQ(c.system.n, 20);
}

TEST(Config, SetStopTimeInfIsAllowed) {
  const Config c = parse_config_text("[stop]\ntime = 5\n", "t", {"stop.time=inf"});
  EXPECT_TRUE(std::isinf(c.stop.time));
}

TEST(Config, SetValueErrorNamesTheSetArgumentNotTheFile) {
  const std::string m = error_of("[system]\nn = 100\n", {"system.n=-5"});
  EXPECT_CONTAINS(m, "--set system.n");
  EXPECT_CONTAINS(m, "-5");
  EXPECT_CONTAINS(m, "must be an integer from 1 to");
  EXPECT_EQ(m.find("run.toml"), std::string::npos) << m;
}

TEST(Config, SetUnknownKeyNamesTheKeyAndTheAllowedKeys) {
  const std::string m = error_of("", {"engine.kidn=ed"});
  EXPECT_CONTAINS(m, "--set engine.kidn");
  EXPECT_CONTAINS(m, "unknown key 'engine.kidn'");
  EXPECT_CONTAINS(m, "kind, skin");
}

TEST(Config, SetUnknownSectionIsAnError) {
  const std::string m = error_of("", {"sytem.n=5"});
  EXPECT_CONTAINS(m, "--set sytem");
  EXPECT_CONTAINS(m, "unknown section [sytem]");
  EXPECT_CONTAINS(m, "system, initial, collision, engine, ts, stop, output");
}

TEST(Config, MalformedSetWithoutDotIsAnError) {
  const std::string m = error_of("", {"n=5"});
  EXPECT_CONTAINS(m, "--set n=5");
  EXPECT_CONTAINS(m, "section.key=value");
}

TEST(Config, MalformedSetWithoutEqualsIsAnError) {
  const std::string m = error_of("", {"system.n"});
  EXPECT_CONTAINS(m, "--set system.n");
  EXPECT_CONTAINS(m, "section.key=value");
}

TEST(Config, MalformedSetWithEmptyOrNestedPartsIsAnError) {
  for (const std::string bad : {".n=5", "system.=5", "system.n.x=5", "=5"}) {
    const std::string m = error_of("", {bad});
    EXPECT_CONTAINS(m, "--set " + bad);
    EXPECT_CONTAINS(m, "section.key=value");
  }
}

TEST(Config, SetIntoASectionThatIsNotATableIsAnError) {
  const std::string m = error_of("system = 3\n", {"system.n=5"});
  EXPECT_CONTAINS(m, "system.n=5");
  EXPECT_CONTAINS(m, "[system]");
}

TEST(Config, SetWithAnArrayForANumberIsAnError) {
  const std::string m = error_of("", {"system.n=[1, 2]"});
  EXPECT_CONTAINS(m, "--set system.n: system.n = [1, 2]: must be an integer");
}

TEST(Config, CheckpointIntervalIsWallSecondsAtLeastZero) {
  EXPECT_EQ(parse_config_text("", "t", {"output.checkpoint_every=0"}).output.checkpoint_every, 0.0);
  EXPECT_CONTAINS(error_of("", {"output.checkpoint_every=-1"}), "output.checkpoint_every = -1: must be a number of wall seconds >= 0");
}

TEST(Config, SnapshotFormatsAreAListOfDistinctKnownNames) {
  EXPECT_EQ(parse_config_text("", "t", {"output.snapshot_formats=[\"xyz\", \"h5md\"]"}).output.snapshot_formats,
            (std::vector<SnapshotFormat>{SnapshotFormat::xyz, SnapshotFormat::h5md}));
  EXPECT_EQ(parse_config_text("", "t", {"output.snapshot_formats=xyz"}).output.snapshot_formats,
            std::vector<SnapshotFormat>{SnapshotFormat::xyz});
  EXPECT_CONTAINS(error_of("", {"output.snapshot_formats=[\"h5md\", \"pdf\"]"}),
                  "output.snapshot_formats = [\"h5md\", \"pdf\"]: must be a list of distinct names from \"h5md\", \"xyz\"");
  EXPECT_CONTAINS(error_of("", {"output.snapshot_formats=[\"xyz\", \"xyz\"]"}), "distinct");
  EXPECT_CONTAINS(error_of("", {"output.snapshot_formats=[]", "output.snapshot_every=1"}),
                  "output.snapshot_formats is empty");
  EXPECT_CONTAINS(error_of("", {"output.snapshot_every=-1"}), "output.snapshot_every = -1: must be a number >= 0");
}

TEST(Config, SnapshotPrecisionIsSingleOrDouble) {
  EXPECT_EQ(parse_config_text("", "t").output.snapshot_precision, SnapshotPrecision::single);
  EXPECT_EQ(parse_config_text("", "t", {"output.snapshot_precision=double"}).output.snapshot_precision,
            SnapshotPrecision::double_);
  EXPECT_EQ(parse_config_text("", "t", {"output.snapshot_precision=single"}).output.snapshot_precision,
            SnapshotPrecision::single);
  EXPECT_CONTAINS(error_of("", {"output.snapshot_precision=half"}),
                  "output.snapshot_precision = \"half\": must be one of \"single\", \"double\"");
  EXPECT_CONTAINS(error_of("", {"output.snapshot_precision=32"}), "output.snapshot_precision");
  // The resolved configuration names it, so that config.toml runs the same again.
  EXPECT_CONTAINS(to_toml_text(parse_config_text("", "t", {"output.snapshot_precision=double"})),
                  "snapshot_precision = \"double\"");
}

TEST(Config, NonIntegralExponentIsNotAnInteger) {
  const std::string m = error_of("", {"system.n=1.5e0"});
  EXPECT_CONTAINS(m, "--set system.n");
  EXPECT_CONTAINS(m, "must be an integer");
}

// ---------------------------------------------------------------------------------------
// Box length

TEST(Config, BoxLength2DFromVolumeFraction) {
  // L = sqrt(N pi R^2 / Vf) = sqrt(100 * pi * 0.25 / 0.25) = sqrt(100 pi) = 17.724538509055160...
  const Config c = parse_config_text("[system]\nn = 100\nradius = 0.5\nvolume_fraction = 0.25\n", "t");
  EXPECT_NEAR(ballagg::resolved_box_length(c), 17.724538509055160, 1e-12);
}

TEST(Config, BoxLength2DOfTheDefaults) {
  // sqrt(2500 * pi * 0.04 / 0.2) = sqrt(500 pi) = 39.633272976060105
  EXPECT_NEAR(ballagg::resolved_box_length(parse_config_text("", "t")), 39.633272976060105, 1e-12);
}

TEST(Config, BoxLength3DFromVolumeFraction) {
  // L = cbrt(N 4/3 pi R^3 / Vf) = cbrt(1000 * 4/3 * pi * 0.125 / 0.1) = cbrt(5000 pi / 3) = 17.36465692...
  const Config c =
      parse_config_text("[system]\ndimension = 3\nn = 1000\nradius = 0.5\nvolume_fraction = 0.1\n", "t");
  EXPECT_NEAR(ballagg::resolved_box_length(c), 17.364656928926813, 1e-12);
}

TEST(Config, BoxLength3DUnitSpheres) {
  // 3 spheres of radius 1 at Vf = pi / 8: L^3 = 3 * 4/3 pi / (pi / 8) = 32, L = cbrt(32)
  Config c = parse_config_text("[system]\ndimension = 3\nn = 3\nradius = 1.0\n", "t");
  c.system.volume_fraction = std::numbers::pi / 8.0;
  EXPECT_NEAR(ballagg::resolved_box_length(c), 3.1748021039363987, 1e-12);
}

TEST(Config, GivenBoxLengthWinsOverTheFormula) {
  Config c = parse_config_text("[system]\nbox_length = 7.25\nn = 9999\n", "t");
  EXPECT_EQ(ballagg::resolved_box_length(c), 7.25);
}

// ---------------------------------------------------------------------------------------
// Round trip of the resolved TOML

TEST(Config, DefaultsRoundTripThroughTomlText) {
  const Config c = parse_config_text("", "t");
  const Config back = parse_config_text(ballagg::to_toml_text(c), "resolved.toml");
  expect_same_config(c, back);
  EXPECT_EQ(ballagg::to_toml_text(back), ballagg::to_toml_text(c));
}

TEST(Config, EveryKeyRoundTripsThroughTomlText) {
  const Config c = parse_config_text(kEveryKey, "t");
  const Config back = parse_config_text(ballagg::to_toml_text(c), "resolved.toml");
  expect_same_config(c, back);
}

TEST(Config, FileConfigRoundTripsThroughTomlText) {
  const Config c = parse_config_text(
      "[system]\nbox_length = 0.1\ndimension = 3\n[initial]\npositions = \"file\"\nfile = \"dir with space/a \\\"q\\\".csv\"\n"
      "[stop]\ntime = 2.5\nwall_seconds = 1e-3\n",
      "t");
  const Config back = parse_config_text(ballagg::to_toml_text(c), "resolved.toml");
  expect_same_config(c, back);
  EXPECT_EQ(back.initial.file, "dir with space/a \"q\".csv");
}

TEST(Config, NumbersThatNeedSeventeenDigitsRoundTripExactly) {
  Config c = parse_config_text("", "t");
  c.system.radius = 0.1 + 0.2;  // 0.30000000000000004
  c.system.volume_fraction = 1.0 / 3.0;
  c.collision.tc_time = 1e-300;
  c.engine.skin = std::nextafter(0.5, 1.0);
  c.initial.seed = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
  const Config back = parse_config_text(ballagg::to_toml_text(c), "resolved.toml");
  expect_same_config(c, back);
}

// ---------------------------------------------------------------------------------------
// Errors: unknown keys and sections

TEST(Config, UnknownKeyNamesKeyLineAndAllowedKeys) {
  const std::string m = error_of("[system]\nn = 10\n\nradus = 0.5\n");
  EXPECT_CONTAINS(m, "run.toml:4");
  EXPECT_CONTAINS(m, "unknown key 'system.radus'");
  EXPECT_CONTAINS(m, "boundary, box_length, density, dimension, mass, n, radii, radius, radius_distribution, radius_exponent, radius_max, radius_min, radius_sigma, radius_weights, volume_fraction");
}

TEST(Config, UnknownKeyInEverySectionIsReported) {
  const char* sections[] = {"system", "initial", "collision", "engine", "stop", "output"};
  for (const std::string s : sections) {
    const std::string m = error_of("# comment\n[" + s + "]\nbogus = 1\n");
    EXPECT_CONTAINS(m, "run.toml:3");
    EXPECT_CONTAINS(m, "'" + s + ".bogus'");
  }
}

TEST(Config, UnknownSectionNamesSectionAndLine) {
  const std::string m = error_of("[system]\nn = 4\n\n[outputs]\nxyz = false\n");
  EXPECT_CONTAINS(m, "run.toml:4");
  EXPECT_CONTAINS(m, "[outputs]");
  EXPECT_CONTAINS(m, "system, initial, collision, engine, ts, stop, output");
}

TEST(Config, KeyOutsideAnySectionIsAnError) {
  const std::string m = error_of("n = 4\n");
  EXPECT_CONTAINS(m, "run.toml:1");
  EXPECT_CONTAINS(m, "'n'");
}

TEST(Config, NestedTableInsideASectionIsAnUnknownKey) {
  const std::string m = error_of("[system]\nn = 4\n[system.extra]\nx = 1\n");
  EXPECT_CONTAINS(m, "run.toml:3");
  EXPECT_CONTAINS(m, "system.extra");
}

TEST(Config, SectionThatIsNotATableIsAnError) {
  const std::string m = error_of("\nsystem = 5\n");
  EXPECT_CONTAINS(m, "run.toml:2");
  EXPECT_CONTAINS(m, "system must be a section ([system])");
  EXPECT_CONTAINS(m, "integer");
}

// ---------------------------------------------------------------------------------------
// Errors: types, ranges, non-finite values

TEST(Config, WrongTypeNamesKeyLineAndWhatIsAllowed) {
  struct Case {
    std::string text, key, allowed;
  };
  const std::vector<Case> cases = {
      {"[system]\n\nn = \"many\"\n", "system.n", "integer"},
      {"[system]\n\ndimension = 2.5\n", "system.dimension", "must be 2 or 3"},
      {"[system]\n\nradius = \"big\"\n", "system.radius", "number"},
      {"[system]\n\nboundary = 3\n", "system.boundary", "\"walls\", \"periodic\""},
      {"[initial]\n\nzero_momentum = 1\n", "initial.zero_momentum", "true or false"},
      {"[initial]\n\nfile = 5\n", "initial.file", "a string"},
      {"[initial]\n\npositions = true\n", "initial.positions", "\"lattice\", \"random\", \"file\""},
      {"[initial]\n\nspeed = [1, 2]\n", "initial.speed", "number"},
      {"[output]\n\nxyz = \"yes\"\n", "output.xyz", "true or false"},
      {"[engine]\n\nkind = \"fast\"\n", "engine.kind", "\"ed\", \"ed-naive\", \"ts\""},
      {"[ts]\n\nmodel = \"soft\"\n", "ts.model", "\"rigid\", \"almost-rigid\", \"non-rigid\""},
      {"[ts]\n\ndt_rule = 3\n", "ts.dt_rule", "\"growth\", \"adaptive\""},
      {"[ts]\n\nmax_iterations = 2.5\n", "ts.max_iterations", "integer"},
      {"[collision]\n\noutcome = \"merge\"\n", "collision.outcome", "\"stick\", \"bounce\""},
      {"[initial]\n\nvelocities = \"maxwell\"\n", "initial.velocities", "\"fixed-speed\", \"uniform\", \"gaussian\""},
      {"[stop]\n\nclusters = 1.5\n", "stop.clusters", "integer"},
      {"[stop]\n\ntime = 1979-05-27\n", "stop.time", "number"},
  };
  for (const Case& c : cases) {
    const std::string m = error_of(c.text);
    EXPECT_CONTAINS(m, "run.toml:3");
    EXPECT_CONTAINS(m, c.key + " =");
    EXPECT_CONTAINS(m, c.allowed);
  }
}

TEST(Config, OutOfRangeValuesAreRejectedForEveryKeyWithARange) {
  struct Case {
    std::string section, key, value, allowed;
  };
  const std::vector<Case> cases = {
      {"system", "dimension", "1", "must be 2 or 3"},
      {"system", "dimension", "4", "must be 2 or 3"},
      {"system", "n", "0", "from 1 to 100000000"},
      {"system", "n", "100000001", "from 1 to 100000000"},
      {"system", "volume_fraction", "0", "(0, 1)"},
      {"system", "volume_fraction", "1", "(0, 1)"},
      {"system", "volume_fraction", "-0.1", "(0, 1)"},
      {"system", "box_length", "0", "> 0"},
      {"system", "box_length", "-3", "> 0"},
      {"system", "radius", "0", "> 0"},
      {"system", "radius", "-0.2", "> 0"},
      {"system", "mass", "0", "> 0"},
      {"system", "mass", "-1", "> 0"},
      {"initial", "speed", "-1", ">= 0"},
      {"initial", "seed", "-1", ">= 0"},
      {"collision", "restitution", "-0.01", "[0, 1]"},
      {"collision", "restitution", "1.01", "[0, 1]"},
      {"collision", "tc_time", "-0.5", ">= 0"},
      {"engine", "skin", "0", "> 0"},
      {"engine", "skin", "-1", "> 0"},
      {"stop", "clusters", "0", ">= 1"},
      {"stop", "time", "0", "> 0"},
      {"stop", "time", "-1", "> 0"},
      {"stop", "wall_seconds", "0", "> 0"},
      {"output", "timeseries_interval", "-1", ">= 0"},
      {"ts", "dt_factor", "0", "(0, 1]"},
      {"ts", "dt_factor", "1.5", "(0, 1]"},
      {"ts", "dt_growth", "0.5", "[1, 1000]"},
      {"ts", "delta_w", "0", "> 0"},
      {"ts", "alpha", "0", "> 0"},
      {"ts", "gamma", "-1", ">= 0"},
      {"ts", "delta", "0", "> 0"},
      {"ts", "c_bar", "-0.1", ">= 0"},
      {"ts", "c_min", "1", "[0, 1)"},
      {"ts", "c_max", "1.5", "(0, 1]"},
      {"ts", "beta_bar", "0", "> 0"},
      {"ts", "beta_max", "-2", "> 0"},
      {"ts", "lambda0", "-1", ">= 0"},
      {"ts", "eps_s", "0", "(0, 1)"},
      {"ts", "eps_c", "1", "(0, 1)"},
      {"ts", "max_iterations", "0", "from 1 to 100000000"},
      {"ts", "max_link_rounds", "0", "from 1 to 1000000"},
      {"ts", "bond_stretch", "0", "(0, 1]"},
      {"ts", "bond_stretch", "1.5", "(0, 1]"},
      {"ts", "stall_iterations", "-1", "from 0 (off) to 100000000"},
      {"ts", "retreat_overlap", "0", "(0, 1]"},
      {"ts", "retreat_overlap", "1.2", "(0, 1]"},
      {"ts", "retreat_pairs", "0", "from 1 to 1000000000"},
      {"ts", "sweep_reuse_margin", "-0.5", "[0, 1000]"},
      {"ts", "sweep_reuse_margin", "nan", "[0, 1000]"},
      {"ts", "fall_back", "\"back\"", "\"retreat\", \"keep-flight\""},
  };
  for (const Case& c : cases) {
    const std::string m = error_of("[" + c.section + "]\n" + c.key + " = " + c.value + "\n");
    SCOPED_TRACE(c.section + "." + c.key + " = " + c.value);
    EXPECT_CONTAINS(m, "run.toml:2");
    EXPECT_CONTAINS(m, c.section + "." + c.key + " = " + c.value);
    EXPECT_CONTAINS(m, c.allowed);
  }
}

TEST(Config, NonFiniteValuesAreRejectedWhereInfinityIsNotAllowed) {
  struct Case {
    std::string section, key;
  };
  const std::vector<Case> cases = {
      {"system", "volume_fraction"}, {"system", "box_length"},   {"system", "radius"},
      {"system", "mass"},            {"system", "n"},            {"system", "dimension"},
      {"initial", "speed"},          {"initial", "seed"},        {"collision", "restitution"},
      {"collision", "tc_time"},      {"engine", "skin"},         {"stop", "clusters"},
      {"output", "timeseries_interval"},
  };
  for (const Case& c : cases) {
    for (const std::string v : {"nan", "inf", "-inf"}) {
      SCOPED_TRACE(c.section + "." + c.key + " = " + v);
      const std::string m = error_of("[" + c.section + "]\n\n" + c.key + " = " + v + "\n");
      EXPECT_CONTAINS(m, "run.toml:3");
      EXPECT_CONTAINS(m, c.section + "." + c.key + " = ");
      EXPECT_CONTAINS(m, "must be");
    }
  }
}

TEST(Config, NanAndNegativeInfinityAreRejectedForStopLimits) {
  for (const std::string key : {"time", "wall_seconds"}) {
    for (const std::string v : {"nan", "-inf"}) {
      const std::string m = error_of("[stop]\n" + key + " = " + v + "\n");
      EXPECT_CONTAINS(m, "run.toml:2");
      EXPECT_CONTAINS(m, "stop." + key);
      EXPECT_CONTAINS(m, "inf for no limit");
    }
  }
}

TEST(Config, NonFiniteSetValueNamesTheSetArgument) {
  const std::string m = error_of("", {"system.radius=nan"});
  EXPECT_CONTAINS(m, "--set system.radius");
  EXPECT_CONTAINS(m, "must be a number > 0");
}

// ---------------------------------------------------------------------------------------
// Errors: rules involving several keys

TEST(Config, VolumeFractionAndBoxLengthTogetherAreRejected) {
  const std::string m = error_of("[system]\nvolume_fraction = 0.1\nbox_length = 20\n");
  EXPECT_CONTAINS(m, "system.volume_fraction");
  EXPECT_CONTAINS(m, "system.box_length");
  EXPECT_CONTAINS(m, "run.toml");
}

TEST(Config, FilePositionsWithoutFileAreRejected) {
  const std::string m = error_of("[system]\nbox_length = 20\n[initial]\npositions = \"file\"\n");
  EXPECT_CONTAINS(m, "initial.file");
  EXPECT_CONTAINS(m, "run.toml");
}

TEST(Config, TsSectionIsReadAndWrittenBack) {
  const Config c = parse_config_text("[engine]\nkind = \"ts\"\n[ts]\nmodel = \"non-rigid\"\ndt_factor = 0.005\n"
                                     "dt_rule = \"adaptive\"\neps_c = 1e-4\nmax_iterations = 500\n"
                                     "bond_stretch = 0.25\nstall_iterations = 400\nretreat_overlap = 0.75\n"
                                     "retreat_pairs = 12\nfall_back = \"retreat\"\nsweep_reuse_margin = 2\n",
                                     "t");
  EXPECT_EQ(c.engine.kind, ballagg::EngineKind::ts);
  EXPECT_EQ(c.ts.model, ballagg::TsModel::non_rigid);
  EXPECT_EQ(c.ts.dt_rule, ballagg::TsDtRule::adaptive);
  EXPECT_DOUBLE_EQ(c.ts.dt_factor, 0.005);
  EXPECT_DOUBLE_EQ(c.ts.daha.eps_c, 1e-4);
  EXPECT_EQ(c.ts.daha.max_iterations, 500);
  EXPECT_DOUBLE_EQ(c.ts.bond_stretch, 0.25);
  EXPECT_EQ(c.ts.daha.stall_iterations, 400);
  EXPECT_DOUBLE_EQ(c.ts.retreat_overlap, 0.75);
  EXPECT_EQ(c.ts.retreat_pairs, 12);
  EXPECT_EQ(c.ts.fall_back, ballagg::TsFallBack::retreat);
  EXPECT_DOUBLE_EQ(c.ts.sweep_reuse_margin, 2.0);
  const Config back = parse_config_text(ballagg::to_toml_text(c), "back");
  EXPECT_EQ(ballagg::to_toml_text(back), ballagg::to_toml_text(c));
  EXPECT_CONTAINS(ballagg::to_toml_text(c), "[ts]\nmodel = \"non-rigid\"");
}

// The rigid model's DAHA defaults were tuned at N = 10^6; the per-sphere models keep the
// earlier set (ts_settings.hpp); a key given in the file wins over either.
TEST(Config, TsDahaDefaultsFollowTheModelAndKeysOverrideThem) {
  const auto daha_of = [](const std::string& ts_keys) {
    return parse_config_text("[engine]\nkind = \"ts\"\n[ts]\n" + ts_keys, "t").ts.daha;
  };
  const ballagg::DahaParameters rigid = daha_of("");
  EXPECT_DOUBLE_EQ(rigid.delta, ballagg::DahaParameters{}.delta);
  EXPECT_EQ(rigid.stall_iterations, ballagg::DahaParameters{}.stall_iterations);
  for (const char* model : {"almost-rigid", "non-rigid"}) {
    const ballagg::DahaParameters p = daha_of(std::string("model = \"") + model + "\"\n");
    EXPECT_DOUBLE_EQ(p.delta, 2.4) << model;
    EXPECT_DOUBLE_EQ(p.c_min, 0.229) << model;
    EXPECT_EQ(p.stall_iterations, 440) << model;
    EXPECT_NE(p.delta, rigid.delta) << model;
  }
  const ballagg::DahaParameters given = daha_of("model = \"non-rigid\"\ndelta = 3\n");
  EXPECT_DOUBLE_EQ(given.delta, 3.0);
  EXPECT_DOUBLE_EQ(given.alpha, 0.043);
}

TEST(Config, TsPaperMethodTakesThePaperConstantsAndReadsBack) {
  const Config c = parse_config_text("[engine]\nkind = \"ts\"\n[ts]\nmethod = \"paper\"\nmodel = \"almost-rigid\"\n", "t");
  EXPECT_EQ(c.ts.method, ballagg::TsMethod::paper);
  EXPECT_TRUE(c.ts.daha.printed_stopping);
  EXPECT_DOUBLE_EQ(c.ts.daha.c_min, 0.0);
  EXPECT_DOUBLE_EQ(c.ts.daha.c_max, 1.0);
  EXPECT_DOUBLE_EQ(c.ts.daha.beta_bar, ballagg::kPaperBetaBar);
  EXPECT_EQ(c.ts.daha.stall_iterations, 0);
  const std::string text = ballagg::to_toml_text(c);
  EXPECT_CONTAINS(text, "method = \"paper\"");
  EXPECT_EQ(text.find("fall_back"), std::string::npos);
  EXPECT_EQ(text.find("bond_stretch"), std::string::npos);
  EXPECT_EQ(ballagg::to_toml_text(parse_config_text(text, "resolved")), text);
  // Ours writes no method key: the configuration files of its runs stay as they were.
  const Config ours = parse_config_text("[engine]\nkind = \"ts\"\n[ts]\nmodel = \"almost-rigid\"\n", "t");
  EXPECT_EQ(ours.ts.method, ballagg::TsMethod::ours);
  EXPECT_EQ(ballagg::to_toml_text(ours).find("method"), std::string::npos);
}

TEST(Config, TsPaperMethodRefusesTheRigidModelAndOurKeys) {
  EXPECT_CONTAINS(error_of("[ts]\nmethod = \"paper\"\n"),
                  "run.toml:2: ts.method = \"paper\": needs ts.model = \"non-rigid\" (3.5) or \"almost-rigid\"");
  EXPECT_CONTAINS(error_of("[ts]\nmethod = \"paper\"\nmodel = \"rigid\"\n"), "the rigid model");
  for (const char* key : {"fall_back = \"retreat\"", "retreat_pairs = 4", "retreat_overlap = 0.5",
                          "sweep_reuse_margin = 1", "bond_stretch = 0.2"}) {
    const std::string m = error_of(std::string("[ts]\nmethod = \"paper\"\nmodel = \"non-rigid\"\n") + key + "\n");
    EXPECT_CONTAINS(m, "ts.method = \"paper\": the paper's method has no fall-back") << key;
    EXPECT_CONTAINS(m, std::string(key).substr(0, std::string(key).find(' '))) << key;
  }
  EXPECT_CONTAINS(error_of("[ts]\nmethod = \"theirs\"\n"), "must be one of \"ours\", \"paper\"");
}

TEST(Config, TsSectionIsLeftOutOfTheResolvedConfigOfOtherEngines) {
  const Config c = parse_config_text("[ts]\nmodel = \"non-rigid\"\n", "t");
  EXPECT_EQ(ballagg::to_toml_text(c).find("[ts]"), std::string::npos);
}

TEST(Config, TsWithBounceIsRejected) {
  const std::string m = error_of("[engine]\nkind = \"ts\"\n[collision]\noutcome = \"bounce\"\n");
  EXPECT_CONTAINS(m, "collision.outcome must be \"stick\"");
}

TEST(Config, TsDampingBoundsMustBeOrdered) {
  const std::string m = error_of("[ts]\nc_min = 0.5\nc_max = 0.4\n");
  EXPECT_CONTAINS(m, "ts.c_min = 0.5 is larger than ts.c_max = 0.4");
}

TEST(Config, UnknownTsKeyIsListedWithTheKnownOnes) {
  const std::string m = error_of("[ts]\ndt = 0.1\n");
  EXPECT_CONTAINS(m, "unknown key 'ts.dt'");
  EXPECT_CONTAINS(m, "dt_factor");
}

TEST(Config, FilePositionsWithoutBoxLengthAreRejected) {
  const std::string m = error_of("[initial]\npositions = \"file\"\nfile = \"a.csv\"\n");
  EXPECT_CONTAINS(m, "system.box_length");
  EXPECT_CONTAINS(m, "run.toml");
}

TEST(Config, FilePositionsWithVolumeFractionInsteadOfBoxLengthAreRejected) {
  const std::string m =
      error_of("[system]\nvolume_fraction = 0.2\n[initial]\npositions = \"file\"\nfile = \"a.csv\"\n");
  EXPECT_CONTAINS(m, "system.box_length");
}

TEST(Config, InitialFileWithoutFilePositionsIsRejected) {
  const std::string m = error_of("[initial]\nfile = \"a.csv\"\n");
  EXPECT_CONTAINS(m, "initial.file");
  EXPECT_CONTAINS(m, "positions = \"file\"");
}

TEST(Config, VolumeFractionAboveTheDensestDiscPackingIsRejected) {
  // pi / (2 sqrt 3) = 0.9069...
  EXPECT_NO_THROW(parse_config_text("[system]\nvolume_fraction = 0.9\n", "t"));
  const std::string m = error_of("[system]\nvolume_fraction = 0.91\n");
  EXPECT_CONTAINS(m, "system.volume_fraction = 0.91");
  EXPECT_CONTAINS(m, "discs");
  EXPECT_CONTAINS(m, "0.9069");
}

TEST(Config, VolumeFractionAboveTheDensestSpherePackingIsRejected) {
  // pi / (3 sqrt 2) = 0.7405...
  EXPECT_NO_THROW(parse_config_text("[system]\ndimension = 3\nvolume_fraction = 0.74\n", "t"));
  const std::string m = error_of("[system]\ndimension = 3\nvolume_fraction = 0.75\n");
  EXPECT_CONTAINS(m, "system.volume_fraction = 0.75");
  EXPECT_CONTAINS(m, "spheres");
  EXPECT_CONTAINS(m, "0.7405");
}

TEST(Config, DensestPackingCheckUsesTheDimensionFromSet) {
  const std::string m = error_of("[system]\nvolume_fraction = 0.8\n", {"system.dimension=3"});
  EXPECT_CONTAINS(m, "system.volume_fraction = 0.8");
  EXPECT_CONTAINS(m, "0.7405");
}

// A rule between keys given by --set names those --set arguments, not "(defaults)" (the
// last --set of a key is the one named); keys from a file name the file.
TEST(Config, RulesBetweenKeysNameTheSetArgumentsThatGaveThem) {
  EXPECT_EQ(error_of("", {"system.box_length=10", "system.volume_fraction=0.3"}, "(defaults)"),
            "--set system.box_length=10 --set system.volume_fraction=0.3: give system.volume_fraction or "
            "system.box_length, not both");
  EXPECT_EQ(error_of("[system]\nbox_length = 10\n", {"system.volume_fraction=0.4", "system.volume_fraction=0.3"})
                .rfind("--set system.volume_fraction=0.3: give", 0), 0u);
  for (const auto& [sets, rule] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"engine.kind=ts", "collision.outcome=bounce"}, "--set engine.kind=ts --set collision.outcome=bounce: "},
           {{"initial.positions=file"}, "--set initial.positions=file: initial.positions = \"file\" needs initial.file"},
           {{"initial.file=a.csv"}, "--set initial.file=a.csv: initial.file is only read"},
           {{"system.volume_fraction=0.95"}, "--set system.volume_fraction=0.95: system.volume_fraction = 0.95"},
           {{"collision.mu_t=0.5"}, "--set collision.mu_t=0.5: collision.mu_t is a key of the rigid-body engine"},
           {{"ts.c_min=0.9", "ts.c_max=0.5"}, "--set ts.c_max: ts.c_min = 0.9 is larger"},
           {{"output.snapshot_every=1", "output.snapshot_formats=[]"}, "--set output.snapshot_every=1 --set "
                                                                       "output.snapshot_formats=[]: "},
           {{"stop.time=2", "initial.time=3"}, "--set stop.time=2 --set initial.time=3: stop.time = 2 is not after "
                                               "initial.time = 3"}}) {
    const std::string m = error_of("", sets, "(defaults)");
    EXPECT_EQ(m.rfind(rule, 0), 0u) << m;
    EXPECT_EQ(m.find("(defaults)"), std::string::npos) << m;
  }
  // From a file, the file is named as before.
  EXPECT_EQ(error_of("[engine]\nkind = \"ts\"\n[collision]\noutcome = \"bounce\"\n").rfind("run.toml: ", 0), 0u);
}

TEST(Config, InitialTimeIsAFiniteTimeNotBelowZero) {
  EXPECT_EQ(parse_config_text("", "t").initial.time, 0.0);
  const Config c = parse_config_text("[initial]\ntime = 2.5\n", "t");
  EXPECT_EQ(c.initial.time, 2.5);
  EXPECT_CONTAINS(ballagg::to_toml_text(c), "time = 2.5\n");
  EXPECT_EQ(parse_config_text(ballagg::to_toml_text(c), "back").initial.time, 2.5);
  // Written only when the clock does not start at 0.
  const std::string text = ballagg::to_toml_text(parse_config_text("", "t"));
  const std::string initial = text.substr(text.find("[initial]"), text.find("[collision]") - text.find("[initial]"));
  EXPECT_EQ(initial.find("time"), std::string::npos) << initial;
  for (const std::string v : {"-1", "nan", "inf", "-inf", "\"soon\""}) {
    const std::string m = error_of("[initial]\ntime = " + v + "\n");
    EXPECT_CONTAINS(m, "run.toml:2: initial.time = ");
    EXPECT_CONTAINS(m, "must be a finite number >= 0");
  }
  EXPECT_CONTAINS(error_of("", {"initial.time=-1"}), "--set initial.time: initial.time = -1: must be a finite number >= 0");
  EXPECT_CONTAINS(error_of("[initial]\ntime = 4\n[stop]\ntime = 4\n"), "stop.time = 4 is not after initial.time = 4");
}

// ---------------------------------------------------------------------------------------
// Errors: TOML syntax and files

TEST(Config, InvalidTomlNamesTheLine) {
  const std::string m = error_of("[system]\nn = 10\nradius = = 3\n");
  EXPECT_CONTAINS(m, "run.toml:3");
  EXPECT_CONTAINS(m, "invalid TOML");
}

TEST(Config, DuplicateKeyIsInvalidToml) {
  const std::string m = error_of("[system]\nn = 10\n\nn = 11\n");
  EXPECT_CONTAINS(m, "run.toml:4");
  EXPECT_CONTAINS(m, "invalid TOML");
}

TEST(Config, UnterminatedSectionHeaderNamesTheLine) {
  const std::string m = error_of("# a\n# b\n[system\n");
  EXPECT_CONTAINS(m, "run.toml:3");
}

TEST(Config, ErrorMessagesAreOneLine) {
  const std::vector<std::string> messages = {
      error_of("[system]\nradus = 1\n"),       error_of("[x]\n"), error_of("[system]\nn = -1\n"),
      error_of("[system]\nn = = \n"),          error_of("", {"bad"}),
      error_of("[initial]\nfile = \"a\"\n"),   error_of("[system]\nvolume_fraction = 0.95\n")};
  for (const std::string& m : messages) {
    EXPECT_FALSE(m.empty());
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(Config, LoadConfigReadsAFileAndNamesItInErrors) {
  TempDir dir;
  const fs::path good = dir.write("good.toml", "[system]\nn = 12\n");
  const Config c = ballagg::load_config(good.string(), {"system.radius=0.3"});
  EXPECT_EQ(c.system.n, 12);
  EXPECT_EQ(c.system.radius, 0.3);
  EXPECT_EQ(c.source, good.string());

  const fs::path bad = dir.write("bad.toml", "[system]\nn = 12\n\n\nsize = 3\n");
  try {
    ballagg::load_config(bad.string(), {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), bad.string() + ":5");
    EXPECT_CONTAINS(e.what(), "system.size");
  }
}

TEST(Config, LoadConfigOfAMissingFileNamesTheFile) {
  TempDir dir;
  const std::string missing = (dir.path() / "missing.toml").string();
  try {
    ballagg::load_config(missing, {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), missing);
    EXPECT_CONTAINS(e.what(), "cannot read");
  }
}

TEST(Config, LoadConfigOfADirectoryIsAnErrorNotTheDefaults) {
  TempDir dir;
  try {
    ballagg::load_config(dir.path().string(), {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), dir.path().string());
    EXPECT_CONTAINS(e.what(), "cannot read");
  }
}

TEST(Config, CrlfConfigFileIsAccepted) {
  const Config c = parse_config_text("[system]\r\nn = 7\r\n\r\n[stop]\r\nclusters = 2\r\n", "t");
  EXPECT_EQ(c.system.n, 7);
  EXPECT_EQ(c.stop.clusters, 2);
}

TEST(Config, ToJsonTextHasEveryKey) {
  const std::string j = ballagg::to_json_text(parse_config_text(kEveryKey, "t"));
  for (const char* key : {"\"dimension\"", "\"n\"", "\"volume_fraction\"", "\"radius\"", "\"mass\"", "\"boundary\"",
                          "\"positions\"", "\"velocities\"", "\"speed\"", "\"zero_momentum\"", "\"seed\"",
                          "\"outcome\"", "\"restitution\"", "\"tc_time\"", "\"kind\"", "\"skin\"", "\"clusters\"",
                          "\"time\"", "\"wall_seconds\"", "\"timeseries_interval\"", "\"xyz\""})
    EXPECT_CONTAINS(j, key);
}

// Found while writing tests/fuzz/fuzz_config: toml++ recursed over a dotted key 100000 parts deep
// until the stack overflowed (a segmentation fault instead of an error).
TEST(Config, AbsurdlyDeepDottedKeyIsAnErrorNotAStackOverflow) {
  std::string deep;
  for (int k = 0; k < 100000; ++k) deep += "a.";
  const std::string m = error_of(deep + "b = 1\n");
  EXPECT_CONTAINS(m, "run.toml:1:");
  EXPECT_CONTAINS(m, "dotted key parts");
  EXPECT_CONTAINS(error_of("[system]\nn = 1\n[" + deep + "b]\n"), "run.toml:3:");
  // Numbers and ordinary keys are far from the limit.
  EXPECT_NO_THROW(ballagg::parse_config_text("[system]\nradius = 0.25\nvolume_fraction = 0.125\n", "ok.toml"));
}

// A --set value that is not UTF-8 would be written into config.toml and summary.json,
// which every TOML and JSON reader then refuses: it is refused with the byte's place.
TEST(Config, SetArgumentThatIsNotUtf8IsRefusedNamingTheByte) {
  for (const std::string& bad : {std::string("initial.file=st\xf6.csv"), std::string("initial.file=e\xf0\xff\xff\xffx"),
                                std::string("initial.file=\xc0\xaf"),           // overlong '/'
                                std::string("initial.file=\xed\xa0\x80"),       // a surrogate
                                std::string("initial.file=\xf4\x90\x80\x80")}) {  // above U+10FFFF
    try {
      ballagg::load_config("", {"initial.positions=file", bad, "system.box_length=10"});
      ADD_FAILURE() << "accepted " << bad;
    } catch (const ballagg::InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("is not UTF-8 text"), std::string::npos) << message;
      const auto first_non_ascii = std::find_if(bad.begin(), bad.end(), [](char c) { return (c & 0x80) != 0; });
      const std::string place = "byte " + std::to_string(first_non_ascii - bad.begin() + 1) + " ";
      EXPECT_NE(message.find(place), std::string::npos) << message;
    }
  }
  // Well-formed multi-byte text is a value like any other.
  const ballagg::Config c =
      ballagg::load_config("", {"initial.positions=file", "initial.file=st\xc3\xb6_\xe2\x82\xac_\xf0\x9f\x98\x80.csv",
                                "system.box_length=10"});
  EXPECT_EQ(c.initial.file, "st\xc3\xb6_\xe2\x82\xac_\xf0\x9f\x98\x80.csv");
}
