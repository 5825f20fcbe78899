#include "ballagg/config/radius_section.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "ballagg/config/value_ranges.hpp"

namespace ballagg {
namespace {

const std::vector<std::string> kLawNames{"monodisperse", "lognormal", "normal", "uniform", "power-law", "discrete"};

std::string law_name(RadiusLaw law) { return '"' + kLawNames[static_cast<int>(law)] + '"'; }

// The laws that read each parameter key.
struct ParameterKey {
  const char* key;
  std::vector<RadiusLaw> laws;
};
const std::vector<ParameterKey>& parameter_keys() {
  using L = RadiusLaw;
  static const std::vector<ParameterKey> keys{
      {"radius_sigma", {L::lognormal, L::normal}},
      {"radius_min", {L::lognormal, L::normal, L::uniform, L::power_law}},
      {"radius_max", {L::lognormal, L::normal, L::uniform, L::power_law}},
      {"radius_exponent", {L::power_law}},
      {"radii", {L::discrete}},
      {"radius_weights", {L::discrete}},
  };
  return keys;
}

// Each parameter key given is one its law reads; each key the law needs is given.
void check_keys_belong_to_the_law(SectionReader& sys, RadiusLaw law) {
  for (const ParameterKey& p : parameter_keys()) {
    if (!sys.has(p.key) || std::count(p.laws.begin(), p.laws.end(), law)) continue;
    std::string laws;
    for (RadiusLaw l : p.laws) laws += (laws.empty() ? "" : " or ") + law_name(l);
    sys.refuse(p.key, fmt::format("is read only with system.radius_distribution = {} (it is {})", laws, law_name(law)));
  }
  using L = RadiusLaw;
  const std::vector<std::pair<L, std::vector<const char*>>> needs{
      {L::lognormal, {"radius_sigma"}}, {L::normal, {"radius_sigma"}}, {L::uniform, {"radius_min", "radius_max"}},
      {L::power_law, {"radius_min", "radius_max", "radius_exponent"}}, {L::discrete, {"radii"}}};
  for (const auto& [needing, keys] : needs)
    for (const char* key : keys)
      if (law == needing && !sys.has(key))
        sys.refuse("radius_distribution", fmt::format("needs system.{} (docs/configuration.md, [system])", key));
}

// The bounds: min < max, within the ratio a box resolves, and keeping enough of a
// truncated law that drawing from it ends.
void check_bounds(SectionReader& sys, const RadiusDistribution& d, double r0) {
  const bool has_min = sys.has("radius_min"), has_max = sys.has("radius_max");
  if (has_min && has_max && !(d.min < d.max))
    sys.refuse("radius_max", fmt::format("must be larger than system.radius_min = {}", d.min));
  if (has_min && has_max && d.max > range::kMaxBoxToRadius * d.min)
    sys.refuse("radius_max", fmt::format("must be at most {:g} times system.radius_min = {} (a box resolves contacts "
                                         "of radii within that ratio)", range::kMaxBoxToRadius, d.min));
  if (d.law != RadiusLaw::lognormal && d.law != RadiusLaw::normal) return;
  const double kept = truncation_acceptance(d, r0);
  if (kept < kMinTruncationAcceptance)
    sys.refuse(has_min ? "radius_min" : "radius_max",
               fmt::format("the bounds keep {:.3g} of the {} law of system.radius = {} and system.radius_sigma = {}: "
                           "must keep at least {:g}", kept, law_name(d.law), r0, d.sigma, kMinTruncationAcceptance));
}

void check_law_parameters(SectionReader& sys, const RadiusDistribution& d, double r0) {
  if (d.law == RadiusLaw::lognormal && !(d.sigma > 1.0 && d.sigma <= kMaxGeometricSigma))
    sys.refuse("radius_sigma", fmt::format("is the lognormal law's geometric standard deviation exp(std of ln R): "
                                           "must be > 1 and at most {:g}", kMaxGeometricSigma));
  if (d.law == RadiusLaw::normal && d.sigma > range::kMaxRadius)
    sys.refuse("radius_sigma", fmt::format("is the normal law's standard deviation: must be at most {:g}", range::kMaxRadius));
  check_bounds(sys, d, r0);
  if (d.law == RadiusLaw::discrete) {
    if (!d.weights.empty() && d.weights.size() != d.radii.size())
      sys.refuse("radius_weights", fmt::format("must give one weight per radius of system.radii ({} radii)", d.radii.size()));
    const auto [lo, hi] = std::minmax_element(d.radii.begin(), d.radii.end());
    if (*hi > range::kMaxBoxToRadius * *lo)
      sys.refuse("radii", fmt::format("the largest radius must be at most {:g} times the smallest (a box resolves "
                                      "contacts of radii within that ratio)", range::kMaxBoxToRadius));
  }
}

// key = value: allowed, from the file line or --set when the key is given, else from
// the configuration's source (a default value).
[[noreturn]] void refuse_value(SectionReader& sys, const Config& c, const std::string& key, double value,
                               const std::string& allowed) {
  if (sys.has(key)) sys.refuse(key, allowed);
  throw InputError(fmt::format("{}: system.{} = {} (default): {}", c.source, key, value, allowed));
}

}  // namespace

void read_radius_keys(SectionReader& sys, SystemConfig& s, bool mass_given) {
  RadiusDistribution& d = s.radius_distribution;
  if (auto v = sys.choice("radius_distribution", kLawNames)) d.law = static_cast<RadiusLaw>(*v);
  const std::string radius_range = fmt::format("from {:g} to {:g}", range::kMinRadius, range::kMaxRadius);
  const auto in_radius_range = [](double r) { return r >= range::kMinRadius && r <= range::kMaxRadius; };
  if (auto v = sys.real("radius_sigma", positive, "must be a number > 0")) d.sigma = *v;
  if (auto v = sys.real("radius_min", in_radius_range, "must be a radius " + radius_range)) d.min = *v;
  if (auto v = sys.real("radius_max", in_radius_range, "must be a radius " + radius_range)) d.max = *v;
  if (auto v = sys.real("radius_exponent", [](double a) { return std::abs(a) <= kMaxPowerLawExponent; },
                        fmt::format("must be a number from {:g} to {:g}", -kMaxPowerLawExponent, kMaxPowerLawExponent)))
    d.exponent = *v;
  if (auto v = sys.reals("radii", in_radius_range, kMaxDiscreteRadii,
                         fmt::format("must be a list of 1 to {} radii, each {}", kMaxDiscreteRadii, radius_range)))
    d.radii = *v;
  if (auto v = sys.reals("radius_weights", [](double w) { return w > 0.0 && w <= 1e300; }, kMaxDiscreteRadii,
                         fmt::format("must be a list of 1 to {} numbers > 0 and at most 1e300", kMaxDiscreteRadii)))
    d.weights = *v;
  s.density = sys.real("density", positive, "must be a number > 0 (mass per volume)");
  if (s.density && mass_given) sys.refuse("density", "give system.mass or system.density, not both");
  check_keys_belong_to_the_law(sys, d.law);
  check_law_parameters(sys, d, s.radius);
}

void check_radius_key_combinations(const Config& c, SectionReader& sys) {
  if (c.initial.positions != InitialPositions::file) return;
  if (polydisperse(c.system))
    sys.refuse("radius_distribution", "draws the radii of a generated start: with initial.positions = \"file\" the "
                                      "file gives them (use \"monodisperse\")");
  if (c.system.density)
    sys.refuse("density", "sets the masses of a generated start: with initial.positions = \"file\" the file gives them");
}

SampledRadii summarize_sampled_radii(const Config& c) {
  const SystemConfig& s = c.system;
  SampledRadii out{s.radius, s.radius, 0.0};
  RadiusSampler sampler(s.radius_distribution, s.radius, c.initial.seed);
  for (std::int64_t k = 0; k < s.n; ++k) {
    const double r = sampler.next();
    out.smallest = k == 0 ? r : std::min(out.smallest, r);
    out.largest = k == 0 ? r : std::max(out.largest, r);
    out.volume += sphere_volume(s.dimension, r);
    out.mass += sphere_mass(s, r);
  }
  return out;
}

void check_sampled_radii(const Config& c, SectionReader& sys, SectionReader& eng) {
  const SampledRadii r = summarize_sampled_radii(c);
  if (r.smallest < range::kMinRadius || r.largest > range::kMaxRadius)
    sys.refuse("radius_distribution", fmt::format("drew radii from {:.3g} to {:.3g}, outside [{:g}, {:g}]: bound the "
                                                  "law with system.radius_min and system.radius_max", r.smallest,
                                                  r.largest, range::kMinRadius, range::kMaxRadius));
  const double lightest = sphere_mass(c.system, r.smallest), heaviest = sphere_mass(c.system, r.largest);
  if (lightest < range::kMinMass || heaviest > range::kMaxMass) {
    const std::string key = c.system.density ? "density" : "mass";
    refuse_value(sys, c, key, c.system.density.value_or(c.system.mass),
                 fmt::format("gives the sampled radii masses from {:.3g} to {:.3g}: they must lie in [{:g}, {:g}]",
                             lightest, heaviest, range::kMinMass, range::kMaxMass));
  }
  const double box = resolved_box_length(c);
  // A lattice spacing that sets the box is refused by check_lattice_spacing, naming it.
  if (box > range::kMaxBoxToRadius * r.smallest && !c.initial.lattice_spacing) {
    const std::string key = c.system.box_length ? "box_length" : "volume_fraction";
    refuse_value(sys, c, key, c.system.box_length.value_or(c.system.volume_fraction.value_or(kDefaultVolumeFraction)),
                 fmt::format("makes the box {:.6g} long, more than {:g} times the smallest sampled radius {:.6g}: "
                             "positions at that box's scale cannot resolve a contact", box, range::kMaxBoxToRadius,
                             r.smallest));
  }
  if (c.engine.skin) {
    const double lo = range::kMinSkinToRadius * r.smallest, hi = range::kMaxSkinToBox * box;
    if (*c.engine.skin < lo || *c.engine.skin > hi)
      eng.refuse("skin", fmt::format("must be from {} to {} ({:g} times the smallest sampled radius to {:g} box "
                                     "lengths)", lo, hi, range::kMinSkinToRadius, range::kMaxSkinToBox));
  }
}

}  // namespace ballagg
