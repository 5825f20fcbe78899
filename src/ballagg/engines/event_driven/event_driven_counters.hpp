#pragma once
// The counters of the event-driven engines (ed, ed-naive), beyond those every engine keeps.
#include <cstdint>

#include "ballagg/engines/engine_counters.hpp"

namespace ballagg {

struct EventDrivenCounters : EngineCounters {
  std::int64_t list_rebuilds = 0;
  std::int64_t rebuilt_spheres = 0;   // spheres re-binned by list rebuilds (work measure)
  std::int64_t pair_predictions = 0;  // contact times computed (work measure)
  std::int64_t queue_peak = 0;        // most events filed at once

  void save(ByteWriter& w) const {
    EngineCounters::save(w);
    for (std::int64_t v : {list_rebuilds, rebuilt_spheres, pair_predictions, queue_peak}) w.put(v);
  }
  void restore(ByteReader& r) {
    EngineCounters::restore(r);
    for (std::int64_t* v : {&list_rebuilds, &rebuilt_spheres, &pair_predictions, &queue_peak})
      *v = r.get<std::int64_t>("counters");
  }
  EngineCounts report() const {
    return {{"list_rebuilds", list_rebuilds}, {"rebuilt_spheres", rebuilt_spheres},
            {"pair_predictions", pair_predictions}, {"event_queue_peak", queue_peak}};
  }
};

}  // namespace ballagg
