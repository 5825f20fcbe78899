#pragma once
#include <memory>

#include "ballagg/engines/engine.hpp"
#include "ballagg/engines/event_driven/event_driven_settings.hpp"

namespace ballagg {

// A larger skin means fewer list rebuilds but longer lists to scan and re-predict. The
// best value measured (docs/performance.md) puts about kSkinNeighbours sphere centres
// within sigma + skin of a sphere in the initial gas, in 2D and in 3D, from volume
// fraction 0.05 to 0.3; never below kMinSkin mean radii. A gas whose collisions bounce
// (collision.outcome = "bounce") forms no aggregates, and in it a dense gas (3D above
// volume fraction 0.24) needs more than the rule: the contact shell alone holds about five
// centres there, and a skin of a free path or less makes every collision rebuild a list or
// two. Its skin is at least kMinBouncingSkin mean radii, the best floor measured on 3D
// elastic gases at volume fractions 0.35 and 0.45. An aggregating gas keeps the rule:
// after each merge the new cluster predicts again every pair of its exposed spheres, and
// longer lists cost more there than the rebuilds they save (docs/profiles.md).
inline constexpr double kSkinNeighbours = 5.0;
inline constexpr double kMinSkin = 0.25;
inline constexpr double kMinBouncingSkin = 0.75;
template <int D>
double default_skin(const State<D>& s, CollisionOutcome outcome);

// Exact event-driven engine (`ed`): analytic contact and wall times, a lazily invalidated
// event queue, and per-cluster neighbour lists with a skin built on a cell grid.
template <int D>
std::unique_ptr<Engine<D>> make_event_driven_engine(const EventDrivenSettings& settings);

// The paper's plain O(N^2) method (`ed-naive`, Appendix A): every event recomputes all
// pair and wall times. The reference the fast engine is checked against. It has no
// neighbour lists: settings.skin is not read.
template <int D>
std::unique_ptr<Engine<D>> make_naive_event_driven_engine(const EventDrivenSettings& settings);

}  // namespace ballagg
