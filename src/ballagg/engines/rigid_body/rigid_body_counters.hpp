#pragma once
// The counters of the rigid-body engine: the event-driven ones (it shares their event
// loop and neighbour lists), and those of rotating bodies.
#include <cstdint>

#include "ballagg/engines/event_driven/event_driven_counters.hpp"

namespace ballagg {

struct RigidBodyCounters : EventDrivenCounters {
  std::int64_t fragmentations = 0;     // catastrophic breakups (Richardson §2.6)
  std::int64_t contact_searches = 0;   // contact_search events handled
  std::int64_t advancement_steps = 0;  // conservative-advancement steps on rotating trajectories
  std::int64_t pose_evaluations = 0;   // orientations computed by the free-rotation propagator

  void save(ByteWriter& w) const {
    EventDrivenCounters::save(w);
    for (std::int64_t v : {fragmentations, contact_searches, advancement_steps, pose_evaluations}) w.put(v);
  }
  void restore(ByteReader& r) {
    EventDrivenCounters::restore(r);
    for (std::int64_t* v : {&fragmentations, &contact_searches, &advancement_steps, &pose_evaluations})
      *v = r.get<std::int64_t>("counters");
  }
  EngineCounts report() const {
    EngineCounts counts = EventDrivenCounters::report();
    counts.insert(counts.end(), {{"first_time_collisions", first_time_collisions}, {"fragmentations", fragmentations},
                                 {"contact_searches", contact_searches}, {"advancement_steps", advancement_steps},
                                 {"pose_evaluations", pose_evaluations}});
    return counts;
  }
};

}  // namespace ballagg
