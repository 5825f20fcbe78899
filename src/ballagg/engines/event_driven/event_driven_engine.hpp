#pragma once
#include <memory>

#include "ballagg/engines/engine.hpp"

namespace ballagg {

struct EventDrivenSettings {
  CollisionSettings collision;
  // Neighbour-list skin (absolute length). Lists are rebuilt for a cluster once it has
  // travelled skin / 2; 0 picks the default (one mean sphere radius, docs/performance.md).
  double skin = 0.0;
};

// Exact event-driven engine (`ed`): analytic contact and wall times, a lazily invalidated
// event queue, and per-cluster neighbour lists with a skin built on a cell grid.
template <int D>
std::unique_ptr<Engine<D>> make_event_driven_engine(const EventDrivenSettings& settings);

// The paper's plain O(N^2) method (`ed-naive`, Appendix A): every event recomputes all
// pair and wall times. The reference the fast engine is checked against.
template <int D>
std::unique_ptr<Engine<D>> make_naive_event_driven_engine(const CollisionSettings& settings);

}  // namespace ballagg
