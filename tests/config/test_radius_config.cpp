// The keys of the radius law and the masses (system.radius_distribution and its
// parameters, system.density): read, written back, and refused with one line naming the
// key and what is allowed.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/config/config.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_config_text(text, "run.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return {};
}

#define EXPECT_REFUSED(text, expected) EXPECT_PRED_FORMAT2(::testing::IsSubstring, expected, error_of(text))

TEST(RadiusConfig, EachLawReadsItsKeysAndWritesThemBack) {
  for (const std::string text : {
           "[system]\nradius = 1.5\nradius_distribution = \"lognormal\"\nradius_sigma = 1.4\n",
           "[system]\nradius_distribution = \"lognormal\"\nradius_sigma = 1.4\nradius_min = 0.1\nradius_max = 0.5\n",
           "[system]\nradius_distribution = \"normal\"\nradius_sigma = 0.02\nradius_min = 0.1\n",
           "[system]\nradius_distribution = \"uniform\"\nradius_min = 0.1\nradius_max = 0.3\ndensity = 2.5\n",
           "[system]\nradius_distribution = \"power-law\"\nradius_min = 0.1\nradius_max = 0.5\nradius_exponent = 3.5\n",
           "[system]\nradius_distribution = \"discrete\"\nradii = [0.1, 0.2]\nradius_weights = [3, 1]\n",
           "[system]\nradius_distribution = \"discrete\"\nradii = 0.25\n",
           "[system]\ndensity = 3.0\n"}) {
    SCOPED_TRACE(text);
    const Config c = parse_config_text(text, "run.toml");
    const std::string written = to_toml_text(c);
    EXPECT_EQ(to_toml_text(parse_config_text(written, "config.toml")), written);
  }
  const Config c = parse_config_text("[system]\nradius_distribution = \"discrete\"\nradii = [0.1, 0.2]\n"
                                     "radius_weights = [3, 1]\n", "run.toml");
  EXPECT_EQ(c.system.radius_distribution.law, RadiusLaw::discrete);
  EXPECT_EQ(c.system.radius_distribution.radii, (std::vector<double>{0.1, 0.2}));
  EXPECT_EQ(c.system.radius_distribution.weights, (std::vector<double>{3.0, 1.0}));
}

TEST(RadiusConfig, OneRadiusWritesTheConfigurationAsBefore) {
  const std::string written = to_toml_text(parse_config_text("", "(defaults)"));
  EXPECT_EQ(written.find("radius_distribution"), std::string::npos);
  EXPECT_EQ(written.find("density"), std::string::npos);
  EXPECT_NE(written.find("mass = 1.0"), std::string::npos);
}

TEST(RadiusConfig, MassesScaleAsRadiusToTheDimensionOrFollowTheDensity) {
  Config c = parse_config_text("[system]\ndimension = 3\nradius = 2.0\nmass = 5.0\nradius_distribution = \"uniform\"\n"
                               "radius_min = 1\nradius_max = 4\n", "run.toml");
  EXPECT_DOUBLE_EQ(sphere_mass(c.system, 2.0), 5.0);
  EXPECT_DOUBLE_EQ(sphere_mass(c.system, 4.0), 40.0);
  EXPECT_DOUBLE_EQ(sphere_mass(c.system, 1.0), 5.0 / 8.0);
  c.system.dimension = 2;
  EXPECT_DOUBLE_EQ(sphere_mass(c.system, 4.0), 20.0);
  c.system.density = 3.0;
  EXPECT_DOUBLE_EQ(sphere_mass(c.system, 2.0), 3.0 * std::numbers::pi * 4.0);
  c.system.dimension = 3;
  EXPECT_DOUBLE_EQ(sphere_mass(c.system, 2.0), 3.0 * 4.0 / 3.0 * std::numbers::pi * 8.0);
  // One radius: system.mass itself.
  const Config one = parse_config_text("[system]\nmass = 0.3\n", "run.toml");
  EXPECT_EQ(sphere_mass(one.system, one.system.radius), 0.3);
}

TEST(RadiusConfig, TheBoxHoldsTheSampledVolumeAtTheVolumeFraction) {
  const Config c = parse_config_text("[system]\nn = 500\ndimension = 3\nvolume_fraction = 0.1\n"
                                     "radius_distribution = \"lognormal\"\nradius_sigma = 1.5\n", "run.toml");
  const SampledRadii s = summarize_sampled_radii(c);
  const std::vector<double> r = sample_radii(c.system.radius_distribution, c.system.radius, 500, c.initial.seed);
  double volume = 0.0;
  for (double x : r) volume += 4.0 / 3.0 * std::numbers::pi * x * x * x;
  EXPECT_DOUBLE_EQ(s.volume, volume);
  EXPECT_DOUBLE_EQ(std::pow(resolved_box_length(c), 3) * 0.1, volume);
}

TEST(RadiusConfig, KeysOfAnotherLawAreRefused) {
  EXPECT_REFUSED("[system]\nradius_sigma = 1.5\n",
                 "run.toml:2: system.radius_sigma = 1.5: is read only with system.radius_distribution = \"lognormal\" "
                 "or \"normal\" (it is \"monodisperse\")");
  EXPECT_REFUSED("[system]\nradius_distribution = \"uniform\"\nradius_min = 1\nradius_max = 2\nradius_exponent = 2\n",
                 "run.toml:5: system.radius_exponent = 2: is read only with system.radius_distribution = \"power-law\"");
  EXPECT_REFUSED("[system]\nradius_distribution = \"lognormal\"\nradius_sigma = 1.5\nradii = [1]\n",
                 "run.toml:4: system.radii = [1]: is read only with system.radius_distribution = \"discrete\"");
  EXPECT_REFUSED("[system]\nradius_distribution = \"discrete\"\nradii = [1]\nradius_max = 2\n",
                 "system.radius_max = 2: is read only with");
}

TEST(RadiusConfig, MissingParametersAreNamed) {
  EXPECT_REFUSED("[system]\nradius_distribution = \"lognormal\"\n",
                 "run.toml:2: system.radius_distribution = \"lognormal\": needs system.radius_sigma");
  EXPECT_REFUSED("[system]\nradius_distribution = \"uniform\"\nradius_min = 1\n", "needs system.radius_max");
  EXPECT_REFUSED("[system]\nradius_distribution = \"power-law\"\nradius_min = 1\nradius_max = 2\n",
                 "needs system.radius_exponent");
  EXPECT_REFUSED("[system]\nradius_distribution = \"discrete\"\n", "needs system.radii");
}

TEST(RadiusConfig, ValuesOutsideTheirRangesAreRefused) {
  EXPECT_REFUSED("[system]\nradius_distribution = \"gamma\"\n", "must be one of \"monodisperse\", \"lognormal\"");
  EXPECT_REFUSED("[system]\nradius_distribution = \"lognormal\"\nradius_sigma = 0.5\n",
                 "system.radius_sigma = 0.5: is the lognormal law's geometric standard deviation");
  EXPECT_REFUSED("[system]\nradius_distribution = \"normal\"\nradius_sigma = -1\n",
                 "system.radius_sigma = -1: must be a number > 0");
  EXPECT_REFUSED("[system]\nradius_distribution = \"uniform\"\nradius_min = 2\nradius_max = 1\n",
                 "system.radius_max = 1: must be larger than system.radius_min = 2");
  EXPECT_REFUSED("[system]\nradius_distribution = \"uniform\"\nradius_min = 1e-30\nradius_max = 1\n",
                 "system.radius_min = 1e-30: must be a radius from 1e-20 to 1e+20");
  EXPECT_REFUSED("[system]\nradius_distribution = \"power-law\"\nradius_min = 1e-3\nradius_max = 1e4\nradius_exponent = 3\n",
                 "must be at most 1e+06 times system.radius_min");
  EXPECT_REFUSED("[system]\nradius_distribution = \"power-law\"\nradius_min = 1\nradius_max = 2\nradius_exponent = 11\n",
                 "system.radius_exponent = 11: must be a number from -10 to 10");
  EXPECT_REFUSED("[system]\nradius_distribution = \"discrete\"\nradii = []\n", "system.radii = []: must be a list of 1 to 1000 radii");
  EXPECT_REFUSED("[system]\nradius_distribution = \"discrete\"\nradii = [1, \"a\"]\n", "must be a list of 1 to 1000 radii");
  EXPECT_REFUSED("[system]\nradius_distribution = \"discrete\"\nradii = [1, 2]\nradius_weights = [1]\n",
                 "system.radius_weights = [1]: must give one weight per radius of system.radii (2 radii)");
  EXPECT_REFUSED("[system]\nradius_distribution = \"discrete\"\nradii = [1, 2]\nradius_weights = [1, 0]\n",
                 "must be a list of 1 to 1000 numbers > 0");
  EXPECT_REFUSED("[system]\nradius_distribution = \"normal\"\nradius = 1\nradius_sigma = 0.01\nradius_min = 2\n",
                 "system.radius_min = 2: the bounds keep");
  EXPECT_REFUSED("[system]\nmass = 2\ndensity = 1\n", "system.density = 1: give system.mass or system.density, not both");
  EXPECT_REFUSED("[system]\ndensity = 0\n", "system.density = 0: must be a number > 0");
}

TEST(RadiusConfig, SampledRadiiAndMassesStayInTheirRanges) {
  // A normal law reaching down to radii near 0: the box cannot resolve the smallest.
  EXPECT_REFUSED("[system]\nn = 100000\nradius = 1\nradius_distribution = \"normal\"\nradius_sigma = 1\n",
                 "system.volume_fraction = 0.2 (default): makes the box");
  EXPECT_REFUSED("[system]\nradius = 1\nradius_distribution = \"uniform\"\nradius_min = 1\nradius_max = 100\n"
                 "density = 1e29\n", "system.density = 1e+29: gives the sampled radii masses from");
}

TEST(RadiusConfig, AStateFileBringsItsOwnRadiiAndMasses) {
  EXPECT_REFUSED("[system]\nbox_length = 10\nradius_distribution = \"uniform\"\nradius_min = 1\nradius_max = 2\n"
                 "[initial]\npositions = \"file\"\nfile = \"x.csv\"\n",
                 "system.radius_distribution = \"uniform\": draws the radii of a generated start");
  EXPECT_REFUSED("[system]\nbox_length = 10\ndensity = 2\n[initial]\npositions = \"file\"\nfile = \"x.csv\"\n",
                 "system.density = 2: sets the masses of a generated start");
}

}  // namespace
}  // namespace ballagg
