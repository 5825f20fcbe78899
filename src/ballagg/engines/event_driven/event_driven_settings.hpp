#pragma once
// The settings of the event-driven engines (`ed`, and `ed-naive`, which reads only the
// collision law). The configuration's [collision] law and engine.skin fill them.
#include <optional>

#include "ballagg/collision/collision_settings.hpp"

namespace ballagg {

// Each cluster keeps at most this many predicted events in the calendar of `ed`, and one
// refill marker for those left out (engines/event_driven/event_calendar.hpp). One event
// and a marker fill a block of two: an aggregating 2D run of 10^6 discs peaks 50 bytes per
// sphere lower than with every event kept, in the same time; a dense elastic gas, where
// each refill predicts about 12 partners again, runs up to 8 % slower
// (docs/profiles.md).
inline constexpr int kKeptEventsPerCluster = 1;

struct EventDrivenSettings {
  CollisionSettings collision;
  // Neighbour-list skin (absolute length). Lists are rebuilt for a cluster once it has
  // travelled skin / 2. Unset: default_skin() (event_driven_engine.hpp).
  std::optional<double> skin;
  // Events kept per cluster (0: all of them). Not a configuration key: the run's results
  // are the same for any value (the tests compare them); only its memory and speed differ.
  int kept_events = kKeptEventsPerCluster;
};

}  // namespace ballagg
