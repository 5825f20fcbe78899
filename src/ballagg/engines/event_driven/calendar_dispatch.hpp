#pragma once
// What the cores of the event-driven engine (ed) and of the rigid-body engine share: their
// events are filed in an EventCalendar; the event loop (event_loop.hpp) takes the next valid
// one, may put it back unhandled, and has it handled by the handler of its kind.
//
// `Core` derives from CalendarDispatch<Core> (CRTP), declares it a friend, and supplies
//   bool valid(const Event&)              whether a filed event still holds (its stamps);
//   EventRecord collide(a, b, t)          EventKind::collision;
//   EventRecord hit_wall(a, b, t)         EventKind::wall;
//   EventRecord rebuild(a, t)             EventKind::list_rebuild;
//   EventRecord search(a, b, t)           EventKind::contact_search, if it files such events;
//   void refill(c)                        predicts cluster c again, if its calendar keeps
//                                         only the earliest event of each cluster: c's
//                                         event was stale (event_calendar.hpp), which the
//                                         loop never sees.
// Every call is resolved at compile time: an event costs no virtual call.
#include <optional>

#include "ballagg/engines/engine.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"

namespace ballagg {

template <class Core>
class CalendarDispatch {
 public:
  std::optional<Event> next_event() {
    while (!calendar_.empty()) {
      const Event e = calendar_.pop();
      if (core().valid(e)) return e;
      if constexpr (requires { core().refill(0); })
        if (calendar_.keeps() == CalendarKeeps::earliest_only) core().refill(calendar_.last_popped_from());
    }
    return std::nullopt;
  }
  void put_back(const Event& e) { calendar_.put_back(e); }

  EventRecord handle(const Event& e) {
    Core& c = core();
    switch (e.kind) {
      case EventKind::collision: return c.collide(e.a, e.b, e.time);
      case EventKind::wall: return c.hit_wall(e.a, e.b, e.time);
      case EventKind::list_rebuild: return c.rebuild(e.a, e.time);
      case EventKind::contact_search:
        if constexpr (requires { c.search(e.a, e.b, e.time); }) return c.search(e.a, e.b, e.time);
        break;  // never filed by a core without contact searches
      case EventKind::time_step: break;  // never filed: time stepping only
    }
    return {};
  }

 protected:
  EventCalendar calendar_;

 private:
  Core& core() { return static_cast<Core&>(*this); }
};

}  // namespace ballagg
