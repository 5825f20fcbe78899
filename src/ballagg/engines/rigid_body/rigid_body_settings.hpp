#pragma once
// The settings of the rigid-body engine: the collision law every engine shares, the
// rigid-body engine's own [collision] keys (RigidBodyLaw), and its neighbour-list skin.
// docs/rigid_body.md describes each key.
#include <optional>

#include "ballagg/collision/collision_settings.hpp"

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
// Which impacts break up (§2.6): none; those above a multiple of the initial mean kinetic
// energy per body (the paper's "fixed threshold determined solely by the initial energy of
// the system"); those above an energy given as such.
enum class Fragmentation { off, initial_energy, energy };

// The default multiples of the initial mean kinetic energy per body: §3's restitution limit
// is that energy itself, and §2.6 names no other multiple for the breakup threshold.
inline constexpr double kDefaultEnergyThresholdFactor = 1.0;
inline constexpr double kDefaultFragmentationFactor = 1.0;

// The [collision] keys only the rigid-body engine reads.
struct RigidBodyLaw {
  Coagulation coagulation = Coagulation::aggregate;
  MergedRadius merged_radius = MergedRadius::constant_density;
  // Sphere coagulation: every merged sphere moves at the initial speed, in the direction
  // of its momentum (model i keeps all speeds equal); false: momentum is conserved.
  bool constant_speed = false;
  RestitutionLaw restitution_law = RestitutionLaw::constant;
  double velocity_unit = 1.0;     // Bridges law: one unit of simulation speed in cm/s
  double mu_t = 0.0, mu_p = 0.0;  // transverse kinetic coefficients (16)-(17)
  // energy_threshold outcome: impacts with less energy than this stick, the others
  // bounce. Unset until a run resolves its default, energy_threshold_factor times the
  // initial mean kinetic energy per body; unset: every impact sticks.
  std::optional<double> energy_threshold;
  // Set when the threshold is (or is to be) derived from the initial energy; unset when
  // energy_threshold was given as an energy.
  std::optional<double> energy_threshold_factor;
  Fragmentation fragmentation = Fragmentation::off;
  // Fragmentation::initial_energy: the threshold as a multiple of the initial mean kinetic
  // energy per body (unset until resolved: kDefaultFragmentationFactor).
  std::optional<double> fragmentation_factor;
  // Impacts with at least this energy that involve an aggregate break the joined body up
  // into its spheres (§2.6). Unset: never (set by a run for Fragmentation::initial_energy).
  std::optional<double> fragmentation_energy;
};

// The cell grid of the rigid-body engine holds at most this many cells per sphere, where
// CellGrid's default is 2. The skin is capped at kSkinDiameters (rigid_body_engine.hpp),
// so in Richardson's dilute gases the narrowest cells the lists allow (2 R_max + skin) are
// far smaller than the spacing of the spheres: model (v) has 8.9 of them per sphere. With 2
// per sphere its cells are 1.66 times wider, and the 27 cells a rebuild scans around each
// sphere it re-bins hold 4.6 times the volume; at 16 per sphere (128 bytes) model (v) gets
// the narrowest cells (docs/profiles.md, "rigid-body"). Not a
// configuration key: the run is the same with any number of cells (the tests compare
// them); only its speed and memory differ.
inline constexpr double kRigidBodyCellsPerSphere = 16.0;

struct RigidBodySettings {
  CollisionSettings collision;  // outcome, eps_n of the constant restitution law, TC model
  RigidBodyLaw law;
  std::optional<double> skin;   // neighbour-list skin (absolute); unset: rigid_body_skin()
  double initial_speed = 0.0;   // the speed law.constant_speed keeps (initial.speed)
  double cells_per_sphere = kRigidBodyCellsPerSphere;  // at most, in the cell grid
  // >= 0: the speed of every sphere made by sphere coagulation; < 0: momentum is conserved.
  double merged_speed() const { return law.constant_speed ? initial_speed : -1.0; }
};

}  // namespace ballagg
