#pragma once
// What the event calendar keeps of the events filed under a cluster (event_calendar.hpp):
// every one, or the earliest only, with the cluster predicted afresh after each of its
// events.
#include <cstdint>

namespace ballagg {

enum class CalendarKeeps : std::uint8_t { every_event, earliest_only };

}  // namespace ballagg
