#pragma once
// What happens when two bodies touch: they stick or bounce, with which restitution, and
// the TC model that keeps inelastic bounces from stalling a run. The [collision] keys
// outcome, restitution and tc_time fill it; every engine's settings hold it as their
// `collision` member, and the collision laws applied to the state (collision/resolve.hpp)
// read it.
#include <optional>

namespace ballagg {

// energy_threshold (rigid-body engine only, Richardson 1995 §3): impacts with less energy
// than a threshold stick, the others bounce.
enum class CollisionOutcome { stick, bounce, energy_threshold };

struct CollisionSettings {
  CollisionOutcome outcome = CollisionOutcome::stick;
  double restitution = 1.0;  // bounce only, in [0, 1]
  // TC model (Luding & McNamara 1998): a bounce involving a body whose previous collision
  // was less than tc_time ago is elastic. Prevents inelastic collapse (infinitely many
  // collisions in a finite time) from stalling a run. Unset until a run resolves its
  // default from the initial state (kDefaultTcFraction, config/config.hpp); unset or 0:
  // the model is off.
  std::optional<double> tc_time;
  double tc() const { return tc_time.value_or(0.0); }
};

}  // namespace ballagg
