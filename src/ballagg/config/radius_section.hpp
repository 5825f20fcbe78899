#pragma once
// The keys of [system] that give the law of the generated spheres' radii and masses
// (system.radius_distribution, radius_sigma, radius_min, radius_max, radius_exponent,
// radii, radius_weights, density), and the checks of the radii they draw.
#include "ballagg/config/config.hpp"
#include "ballagg/config/section_reader.hpp"

namespace ballagg {

// A discrete law lists at most this many radii.
inline constexpr std::size_t kMaxDiscreteRadii = 1000;
// A lognormal law's geometric standard deviation is at most this: a wider law spans more
// than the 10^6 radii within which a box resolves its smallest contact.
inline constexpr double kMaxGeometricSigma = 10.0;
// A power law's exponent alpha lies in [-kMaxPowerLawExponent, kMaxPowerLawExponent]: with
// radius_max / radius_min <= 10^6, (radius_max / radius_min)^(1 - alpha) stays finite.
inline constexpr double kMaxPowerLawExponent = 10.0;

// Reads the keys into s, each checked alone and against the law it belongs to. Throws
// InputError naming the key, its file line (or --set) and what is allowed.
void read_radius_keys(SectionReader& sys, SystemConfig& s, bool mass_given);

// The rules against other sections (a state file brings its own radii and masses).
void check_radius_key_combinations(const Config& c, SectionReader& sys);

// The sampled radii and their masses within the ranges of value_ranges.hpp, the box and
// the skin against the smallest sampled radius. Polydisperse generated starts only.
void check_sampled_radii(const Config& c, SectionReader& sys, SectionReader& eng);

}  // namespace ballagg
