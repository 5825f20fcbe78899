#include "ballagg/config/rigid_body_section.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {

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
  k.fragmentation_energy = col.real("fragmentation_energy", positive, "must be a number > 0 (an energy)");
  note("fragmentation_energy", k.fragmentation_energy.has_value());
  return given;
}

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
  if (has("energy_threshold") && outcome != CollisionOutcome::energy_threshold)
    throw InputError(fmt::format("{}: collision.energy_threshold is only used with collision.outcome = "
                                 "\"energy-threshold\"", origin_of(c, {"collision.energy_threshold", "collision.outcome"})));
  if (k.coagulation != Coagulation::sphere) {
    for (const char* key : {"merged_radius", "constant_speed"})
      if (has(key))
        throw InputError(fmt::format("{}: collision.{} is only used with collision.coagulation = \"sphere\"",
                                     origin_of(c, {"collision.coagulation", "collision." + std::string(key)}), key));
  } else if (k.fragmentation_energy) {
    throw InputError(fmt::format("{}: collision.fragmentation_energy breaks aggregates up: it needs "
                                 "collision.coagulation = \"aggregate\"",
                                 origin_of(c, {"collision.fragmentation_energy", "collision.coagulation"})));
  }
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

}  // namespace ballagg
