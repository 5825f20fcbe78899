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
    case StopReason::output_limit: return "output_limit";
    case StopReason::interrupted: return "interrupted";
  }
  return "unknown";
}

StopReason stop_reason_of(StopCause cause) {
  switch (cause) {
    case StopCause::wall_seconds: return StopReason::wall_seconds;
    case StopCause::output_limit: return StopReason::output_limit;
    case StopCause::signal: return StopReason::interrupted;
    case StopCause::none: break;
  }
  throw std::logic_error("stop_reason_of: the run was not stopped by its guard");
}

}  // namespace ballagg
