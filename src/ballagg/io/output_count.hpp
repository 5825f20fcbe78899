#pragma once
// The refusal of an output interval that would write more rows or frames than allowed,
// shared by the time series and the trajectories (docs/configuration.md, "output").
#include <cmath>
#include <cstdint>
#include <string_view>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {

// Throws InputError when (stop_time - start_time) / interval exceeds `limit` `items`
// ("rows", "frames"); nothing to check without an interval or a finite stop.time.
inline void check_output_count(std::string_view key, double interval, double start_time, double stop_time,
                               std::int64_t limit, std::string_view items) {
  if (!(interval > 0.0) || !std::isfinite(stop_time)) return;
  const double count = (stop_time - start_time) / interval;
  if (count > static_cast<double>(limit))
    throw InputError(fmt::format("{} = {}: {:.3g} {} from t = {} to stop.time = {}; at most {} are allowed (use a "
                                 "larger interval)",
                                 key, interval, count, items, start_time, stop_time, limit));
}

}  // namespace ballagg
