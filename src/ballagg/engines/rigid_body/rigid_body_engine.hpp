#pragma once
// The rigid-body engine (`rigid-body`, Richardson 1995): aggregates that translate and
// rotate as free rigid bodies between collisions, exact contact detection on their rotating
// trajectories, coagulation conserving linear and angular momentum, restitution with
// generalised coefficients, and catastrophic fragmentation. docs/rigid_body.md describes it.
#include <limits>
#include <memory>

#include "ballagg/engines/engine.hpp"

namespace ballagg {

// How colliding bodies coagulate (Richardson's Table I): `aggregate`, they stick at the
// point of contact; `sphere`, the pair becomes one sphere at its centre of mass (test
// models (i) and (ii)).
enum class Coagulation { aggregate, sphere };
// The radius of a sphere made by `sphere` coagulation: constant density, R^3 = R1^3 + R2^3
// (model ii), or the radius of the first (model i: fixed radius).
enum class MergedRadius { constant_density, fixed };
// The normal coefficient of restitution: a constant, or the ice law of Bridges et al.
// (1984) that Richardson's §3 uses.
enum class RestitutionLaw { constant, bridges };

struct RigidBodySettings {
  CollisionOutcome outcome = CollisionOutcome::stick;
  Coagulation coagulation = Coagulation::aggregate;
  MergedRadius merged_radius = MergedRadius::constant_density;
  // >= 0: every sphere made by `sphere` coagulation moves at this speed, in the direction
  // of its momentum (model i keeps all speeds equal); < 0: momentum is conserved.
  double merged_speed = -1.0;
  RestitutionLaw restitution_law = RestitutionLaw::constant;
  double restitution = 1.0;     // eps_n of the constant law
  double velocity_unit = 1.0;   // Bridges law: one unit of simulation speed in cm/s
  double mu_t = 0.0, mu_p = 0.0;  // transverse kinetic coefficients (16)-(17)
  // energy_threshold outcome: impacts with less energy than this stick, the others bounce.
  double energy_threshold = std::numeric_limits<double>::infinity();
  // Impacts with at least this energy that involve an aggregate break the joined body up
  // into its spheres (§2.6). Infinite: never.
  double fragmentation_energy = std::numeric_limits<double>::infinity();
  double tc_time = 0.0;  // TC model of inelastic collapse, as in the event-driven engine
  double skin = 0.0;     // neighbour-list skin (absolute); 0 picks default_skin()
};

// The default neighbour-list skin: the event-driven engine's (about kSkinNeighbours
// neighbours), but at most kSkinDiameters mean diameters. A rebuild costs more here (it
// evaluates the orientations of the partners' bodies), and in the dilute gases of
// Richardson's models a skin of 2-3 diameters was measured fastest (docs/rigid_body.md).
inline constexpr double kSkinDiameters = 2.5;
template <int D>
double rigid_body_skin(const State<D>& s);

template <int D>
std::unique_ptr<Engine<D>> make_rigid_body_engine(const RigidBodySettings& settings);

}  // namespace ballagg
