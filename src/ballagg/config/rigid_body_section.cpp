#include "ballagg/config/rigid_body_section.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {

namespace {

// collision.fragmentation and the keys of its threshold. Without collision.fragmentation, a
// collision.fragmentation_energy alone means "energy" (an absolute threshold).
template <typename Note>
void read_fragmentation_keys(SectionReader& col, RigidBodyLaw& k, Note note) {
  const auto mode = col.choice("fragmentation", {"off", "initial-energy", "energy"});
  k.fragmentation_factor = col.real("fragmentation_factor", positive,
                                    "must be a number > 0 (a multiple of the initial mean kinetic energy per body)");
  note("fragmentation_factor", k.fragmentation_factor.has_value());
  k.fragmentation_energy = col.real("fragmentation_energy", positive, "must be a number > 0 (an energy)");
  note("fragmentation_energy", k.fragmentation_energy.has_value());
  if (mode) k.fragmentation = static_cast<Fragmentation>(*mode);
  else if (k.fragmentation_energy) k.fragmentation = Fragmentation::energy;
  note("fragmentation", mode.has_value());
}

}  // namespace

// The [collision] keys of the rigid-body engine (docs/rigid_body.md). Returns the names of
// those given, so that other engines can refuse them.
std::vector<std::string> read_rigid_body_keys(SectionReader& col, RigidBodyLaw& k) {
  std::vector<std::string> given;
  auto note = [&](const char* key, bool present) { if (present) given.push_back(key); };
  const auto coagulation = col.choice("coagulation", {"aggregate", "sphere"});
  if (coagulation) k.coagulation = static_cast<Coagulation>(*coagulation);
  note("coagulation", coagulation.has_value());
  const auto radius = col.choice("merged_radius", {"constant-density", "fixed"});
  if (radius) k.merged_radius = static_cast<MergedRadius>(*radius);
  note("merged_radius", radius.has_value());
  const auto constant_speed = col.boolean("constant_speed");
  if (constant_speed) k.constant_speed = *constant_speed;
  note("constant_speed", constant_speed.has_value());
  const auto law = col.choice("restitution_law", {"constant", "bridges"});
  if (law) k.restitution_law = static_cast<RestitutionLaw>(*law);
  note("restitution_law", law.has_value());
  const auto unit = col.real("velocity_unit", positive, "must be a number > 0 (cm/s per unit of speed)");
  if (unit) k.velocity_unit = *unit;
  note("velocity_unit", unit.has_value());
  const auto mu_t = col.real("mu_t", [](double v) { return v >= 0.0 && v <= 10.0; },
                             "must be a number in [0, 10] (> 0 opposes the slip; a negative value would drive it "
                             "and create energy)");
  if (mu_t) k.mu_t = *mu_t;
  note("mu_t", mu_t.has_value());
  const auto mu_p = col.real("mu_p", [](double v) { return std::abs(v) <= 10.0; }, "must be a number in [-10, 10]");
  if (mu_p) k.mu_p = *mu_p;
  note("mu_p", mu_p.has_value());
  k.energy_threshold = col.real("energy_threshold", positive, "must be a number > 0 (an energy)");
  note("energy_threshold", k.energy_threshold.has_value());
  k.energy_threshold_factor = col.real("energy_threshold_factor", positive,
                                       "must be a number > 0 (a multiple of the initial mean kinetic energy per body)");
  note("energy_threshold_factor", k.energy_threshold_factor.has_value());
  read_fragmentation_keys(col, k, note);
  return given;
}

namespace {

// collision.fragmentation against its threshold keys and the coagulation.
template <typename Has>
void check_fragmentation_rules(const Config& c, Has has) {
  const RigidBodyLaw& k = c.rigid_body;
  if (k.fragmentation == Fragmentation::off) {
    if (k.fragmentation_energy)
      throw InputError(fmt::format("{}: collision.fragmentation = \"off\" with collision.fragmentation_energy: drop "
                                   "one (collision.fragmentation = \"energy\" uses the energy)",
                                   origin_of(c, {"collision.fragmentation", "collision.fragmentation_energy"})));
  } else if (k.coagulation == Coagulation::sphere) {
    throw InputError(fmt::format("{}: collision.fragmentation breaks aggregates up: it needs collision.coagulation = "
                                 "\"aggregate\"", origin_of(c, {"collision.fragmentation", "collision.fragmentation_energy",
                                                                 "collision.coagulation"})));
  }
  if (k.fragmentation == Fragmentation::energy && !k.fragmentation_energy)
    throw InputError(fmt::format("{}: collision.fragmentation = \"energy\" needs collision.fragmentation_energy (or use "
                                 "collision.fragmentation = \"initial-energy\")",
                                 origin_of(c, {"collision.fragmentation", "collision.fragmentation_energy"})));
  if (has("fragmentation_factor") && k.fragmentation != Fragmentation::initial_energy)
    throw InputError(fmt::format("{}: collision.fragmentation_factor is only used with collision.fragmentation = "
                                 "\"initial-energy\"", origin_of(c, {"collision.fragmentation_factor", "collision.fragmentation"})));
}

}  // namespace

// Rules between the rigid-body keys and the rest.
void check_rigid_body_rules(const Config& c, const std::vector<std::string>& given, bool restitution_given) {
  const RigidBodyLaw& k = c.rigid_body;
  const CollisionOutcome outcome = c.collision.outcome;
  auto has = [&](const char* key) { return std::find(given.begin(), given.end(), key) != given.end(); };
  if (c.engine.kind != EngineKind::rigid_body) {
    if (!given.empty())
      throw InputError(fmt::format("{}: collision.{} is a key of the rigid-body engine: it needs engine.kind = "
                                   "\"rigid-body\"", origin_of(c, {"engine.kind", "collision." + given.front()}), given.front()));
    if (outcome == CollisionOutcome::energy_threshold)
      throw InputError(fmt::format("{}: collision.outcome = \"energy-threshold\" needs engine.kind = \"rigid-body\"",
                                   origin_of(c, {"engine.kind", "collision.outcome"})));
    if (c.stop.aggregated_fraction)
      throw InputError(fmt::format("{}: stop.aggregated_fraction needs engine.kind = \"rigid-body\"",
                                   origin_of(c, {"engine.kind", "stop.aggregated_fraction"})));
    return;
  }
  for (const char* key : {"energy_threshold", "energy_threshold_factor"})
    if (has(key) && outcome != CollisionOutcome::energy_threshold)
      throw InputError(fmt::format("{}: collision.{} is only used with collision.outcome = \"energy-threshold\"",
                                   origin_of(c, {"collision." + std::string(key), "collision.outcome"}), key));
  if (k.coagulation != Coagulation::sphere) {
    for (const char* key : {"merged_radius", "constant_speed"})
      if (has(key))
        throw InputError(fmt::format("{}: collision.{} is only used with collision.coagulation = \"sphere\"",
                                     origin_of(c, {"collision.coagulation", "collision." + std::string(key)}), key));
  }
  check_fragmentation_rules(c, has);
  if (k.constant_speed && c.initial.velocities != InitialVelocities::fixed_speed)
    throw InputError(fmt::format("{}: collision.constant_speed keeps every speed at initial.speed: it needs "
                                 "initial.velocities = \"fixed-speed\"",
                                 origin_of(c, {"collision.constant_speed", "initial.velocities"})));
  if (k.restitution_law == RestitutionLaw::bridges && restitution_given)
    throw InputError(fmt::format("{}: give collision.restitution (a constant) or collision.restitution_law = "
                                 "\"bridges\", not both", origin_of(c, {"collision.restitution", "collision.restitution_law"})));
  if (has("velocity_unit") && k.restitution_law != RestitutionLaw::bridges)
    throw InputError(fmt::format("{}: collision.velocity_unit is only used with collision.restitution_law = "
                                 "\"bridges\"", origin_of(c, {"collision.velocity_unit", "collision.restitution_law"})));
  if (c.system.dimension == 2 && k.mu_p != 0.0)
    throw InputError(fmt::format("{}: collision.mu_p = {}: in 2D the contact has one tangent (use mu_t)",
                                 origin_of(c, {"collision.mu_p", "system.dimension"}), k.mu_p));
}

namespace {

// `energy` (given, or unset) and `factor` (given, or unset: `default_factor`) of one threshold;
// returns the energy in effect, factor x initial_mean_energy unless only the energy was given.
double derived_energy(const Config& c, std::optional<double>& energy, std::optional<double>& factor,
                      double default_factor, double initial_mean_energy, const char* energy_key, const char* factor_key) {
  if (energy && !factor) return *energy;
  factor = factor.value_or(default_factor);
  const double derived = *factor * initial_mean_energy;
  if (energy && *energy != derived)
    throw InputError(fmt::format("{}: collision.{} = {} is not collision.{} = {} times the initial mean kinetic energy "
                                 "per body ({}), which gives {}: give one of the two keys",
                                 origin_of(c, {std::string("collision.") + energy_key, std::string("collision.") + factor_key}),
                                 energy_key, *energy, factor_key, *factor, initial_mean_energy, derived));
  return derived;
}

}  // namespace

void resolve_rigid_body_energies(Config& c, double initial_mean_energy) {
  if (c.engine.kind != EngineKind::rigid_body) return;
  RigidBodyLaw& k = c.rigid_body;
  if (c.collision.outcome == CollisionOutcome::energy_threshold)
    k.energy_threshold = derived_energy(c, k.energy_threshold, k.energy_threshold_factor, kDefaultEnergyThresholdFactor,
                                        initial_mean_energy, "energy_threshold", "energy_threshold_factor");
  if (k.fragmentation != Fragmentation::initial_energy) return;
  if (!(initial_mean_energy > 0.0))
    throw InputError(fmt::format("{}: collision.fragmentation = \"initial-energy\": the bodies start at rest (initial "
                                 "mean kinetic energy 0), so every impact would break up; give collision.fragmentation_energy "
                                 "with collision.fragmentation = \"energy\"", origin_of(c, {"collision.fragmentation"})));
  // The mode says the energy is derived: a fragmentation_energy beside it is checked.
  k.fragmentation_factor = k.fragmentation_factor.value_or(kDefaultFragmentationFactor);
  k.fragmentation_energy = derived_energy(c, k.fragmentation_energy, k.fragmentation_factor, kDefaultFragmentationFactor,
                                          initial_mean_energy, "fragmentation_energy", "fragmentation_factor");
}

}  // namespace ballagg
