#pragma once
// The settings of the event-driven engines (`ed`, and `ed-naive`, which reads only the
// collision law). The configuration's [collision] law and engine.skin fill them.
#include <optional>

#include "ballagg/collision/collision_settings.hpp"
#include "ballagg/engines/event_driven/calendar_keeps.hpp"

namespace ballagg {

// `ed` keeps each cluster's earliest event only, and predicts a cluster afresh after every
// event filed under it (engines/event_driven/event_calendar.hpp): one 32-byte event per
// cluster, where keeping every prediction costs a heap of them in a pool.
inline constexpr CalendarKeeps kEventDrivenCalendar = CalendarKeeps::earliest_only;

struct EventDrivenSettings {
  CollisionSettings collision;
  // Neighbour-list skin (absolute length). Lists are rebuilt for a cluster once it has
  // travelled skin / 2. Unset: default_skin() (event_driven_engine.hpp).
  std::optional<double> skin;
  // What the calendar keeps. Not a configuration key: the run's results are the same
  // either way (the tests compare them); only its memory and speed differ.
  CalendarKeeps calendar = kEventDrivenCalendar;
};

}  // namespace ballagg
