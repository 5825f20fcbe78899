#pragma once
// The settings of the event-driven engines (`ed`, and `ed-naive`, which reads only the
// collision law). The configuration's [collision] law and engine.skin fill them.
#include <optional>

#include "ballagg/collision/collision_settings.hpp"

namespace ballagg {

struct EventDrivenSettings {
  CollisionSettings collision;
  // Neighbour-list skin (absolute length). Lists are rebuilt for a cluster once it has
  // travelled skin / 2. Unset: default_skin() (event_driven_engine.hpp).
  std::optional<double> skin;
};

}  // namespace ballagg
