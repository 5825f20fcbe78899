#pragma once
// What an engine counts. EngineCounters holds the counts every engine keeps and the
// observers read while a run goes on (the progress line, timeseries.csv, Python's
// callbacks); each engine extends it with counters of its own (EventDrivenCounters,
// RigidBodyCounters, TimeSteppingCounters), saves them in its checkpoint section field by
// field, and reports them by name at the end of a run (summary.json).
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "ballagg/core/byte_stream.hpp"

namespace ballagg {

struct EngineCounters {
  std::int64_t events = 0;        // every event handled, list rebuilds included (ts: every step)
  std::int64_t collisions = 0;    // sphere-sphere contacts between different clusters
  std::int64_t merges = 0;        // clusters absorbed (>= sticking collisions: cascades)
  std::int64_t bounces = 0;
  std::int64_t wall_bounces = 0;
  std::int64_t steps = 0;                  // time steps (ts; 0 for the event-driven engines)
  std::int64_t first_time_collisions = 0;  // N_C1: collisions not repeating the bodies' previous pair (rigid-body)

  void save(ByteWriter& w) const {
    for (std::int64_t v : {events, collisions, merges, bounces, wall_bounces, steps, first_time_collisions}) w.put(v);
  }
  void restore(ByteReader& r) {
    for (std::int64_t* v : {&events, &collisions, &merges, &bounces, &wall_bounces, &steps, &first_time_collisions})
      *v = r.get<std::int64_t>("counters");
  }
  bool operator==(const EngineCounters&) const = default;
};

// One of an engine's own counters at the end of a run, under its summary.json key.
struct EngineCount {
  std::string_view key;
  std::variant<std::int64_t, double> value;
  bool operator==(const EngineCount&) const = default;
};
using EngineCounts = std::vector<EngineCount>;

// The value of `key` in counts; throws std::out_of_range when the engine reports none of
// that name and type.
template <class T>
T engine_count(const EngineCounts& counts, std::string_view key) {
  for (const EngineCount& c : counts)
    if (c.key == key && std::holds_alternative<T>(c.value)) return std::get<T>(c.value);
  throw std::out_of_range("the engine reports no counter " + std::string(key) + " of that type");
}

}  // namespace ballagg
