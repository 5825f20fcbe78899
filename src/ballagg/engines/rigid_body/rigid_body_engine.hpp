#pragma once
// The rigid-body engine (`rigid-body`, Richardson 1995): aggregates that translate and
// rotate as free rigid bodies between collisions, exact contact detection on their rotating
// trajectories, coagulation conserving linear and angular momentum, restitution with
// generalised coefficients, and catastrophic fragmentation. docs/rigid_body.md describes it.
#include <memory>

#include "ballagg/engines/engine.hpp"
#include "ballagg/engines/rigid_body/rigid_body_settings.hpp"

namespace ballagg {

// The default neighbour-list skin: the event-driven engine's for an aggregating gas (about
// kSkinNeighbours neighbours), but at most kSkinDiameters mean diameters. A rebuild costs more here (it
// evaluates the orientations of the partners' bodies), and in the dilute gases of
// Richardson's models a skin of 2-3 diameters was measured fastest (docs/rigid_body.md).
inline constexpr double kSkinDiameters = 2.5;
template <int D>
double rigid_body_skin(const State<D>& s);

template <int D>
std::unique_ptr<Engine<D>> make_rigid_body_engine(const RigidBodySettings& settings);

}  // namespace ballagg
