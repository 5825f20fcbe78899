#include "ballagg/engines/engine.hpp"

namespace ballagg {

std::string_view to_string(StopReason r) {
  switch (r) {
    case StopReason::clusters: return "clusters";
    case StopReason::time: return "time";
    case StopReason::wall_seconds: return "wall_seconds";
    case StopReason::no_more_events: return "no_more_events";
    case StopReason::no_collision_possible: return "no_collision_possible";
    case StopReason::aggregated: return "aggregated";
    case StopReason::body_spans_box: return "body_spans_box";
  }
  return "unknown";
}

}  // namespace ballagg
