#include "ballagg/run/collision_law_summary.hpp"

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "ballagg/collision/rigid_impulse.hpp"

namespace ballagg {

namespace {

using Json = nlohmann::ordered_json;

// The reference energy of both derived thresholds (resolve_rigid_body_energies).
constexpr const char* kMeanEnergy =
    "the initial mean kinetic energy per body (translation and rotation, over the bodies at the start)";

// What RigidBodyCore::impact_energy computes.
Json impact_energy() {
  Json j;
  j["formula"] = "1/2 mu |V_1 - V_2|^2, mu = m_1 m_2 / (m_1 + m_2)";
  j["velocities"] = "V_1, V_2: the two bodies' centre-of-mass velocities at the impact (translation only: the spins "
                    "and the velocities of the contact points do not enter)";
  return j;
}

// A threshold: its energy, and the factor and reference it came from, or that it was given.
Json threshold(double energy, const std::optional<double>& factor, const char* energy_key, const char* factor_key) {
  Json j;
  j["energy"] = energy;
  if (factor) {
    j["factor"] = *factor;
    j["derivation"] = std::string("collision.") + factor_key + " x " + kMeanEnergy;
  } else {
    j["factor"] = nullptr;
    j["derivation"] = std::string("collision.") + energy_key + ", given as an energy";
  }
  return j;
}

Json energy_threshold(const RigidBodyLaw& k) {
  Json j = threshold(k.energy_threshold.value_or(0.0), k.energy_threshold_factor, "energy_threshold",
                     "energy_threshold_factor");
  j["rule"] = "an impact with less energy sticks, the others bounce (Richardson §3)";
  return j;
}

Json fragmentation(const RigidBodyLaw& k) {
  Json j;
  j["mode"] = to_string(k.fragmentation);
  if (k.fragmentation == Fragmentation::off || !k.fragmentation_energy) return j;
  j.update(threshold(*k.fragmentation_energy, k.fragmentation_factor, "fragmentation_energy", "fragmentation_factor"));
  j["rule"] = "an impact with at least this energy that involves an aggregate joins the two bodies, then every sphere "
              "flies off with its velocity in the joined body plus an outward radial velocity H r (r from the centre "
              "of mass) that gives back the kinetic energy the joining lost (Richardson §2.6)";
  return j;
}

Json restitution(const Config& c) {
  const RigidBodyLaw& k = c.rigid_body;
  Json j;
  j["law"] = to_string(k.restitution_law);
  if (k.restitution_law == RestitutionLaw::constant) {
    j["eps_n"] = c.collision.restitution;
  } else {
    j["formula"] = "eps_n = (v / v_c)^exponent for v > v_c, 1 for v <= v_c (Bridges, Hatzes & Lin 1984, ice)";
    j["v"] = "the normal speed of the contact points, |u_n| (simulation units) x velocity_unit_cm_per_s";
    j["critical_speed_cm_per_s"] = kBridgesCriticalSpeed;
    j["exponent"] = kBridgesExponent;
    j["velocity_unit_cm_per_s"] = k.velocity_unit;
    j["critical_speed"] = kBridgesCriticalSpeed / k.velocity_unit;  // in simulation units
  }
  j["mu_t"] = k.mu_t;
  if (c.system.dimension == 3) j["mu_p"] = k.mu_p;
  return j;
}

}  // namespace

std::string collision_law_json_text(const Config& c) {
  const RigidBodyLaw& k = c.rigid_body;
  Json j;
  j["outcome"] = to_string(c.collision.outcome);
  j["coagulation"] = to_string(k.coagulation);
  j["impact_energy"] = impact_energy();
  if (c.collision.outcome == CollisionOutcome::energy_threshold) j["energy_threshold"] = energy_threshold(k);
  if (c.collision.outcome != CollisionOutcome::stick) j["restitution"] = restitution(c);
  j["fragmentation"] = fragmentation(k);
  return j.dump();
}

}  // namespace ballagg
