// Micro-benchmarks of the event-driven engine's inner operations (Google Benchmark).
// Run: build/bin/ballagg_micro
#include <benchmark/benchmark.h>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/core/random.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"

namespace {

using namespace ballagg;

void BM_ContactTime2D(benchmark::State& state) {
  Random rng(1, RandomPurpose::positions);
  std::vector<Vec<2>> dx(1024), dv(1024);
  for (int k = 0; k < 1024; ++k) {
    dx[k] = Vec<2>(rng.uniform(-3, 3), rng.uniform(-3, 3));
    dv[k] = Vec<2>(rng.uniform(-1, 1), rng.uniform(-1, 1));
  }
  int k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(contact_time<2>(dx[k], dv[k], 0.4));
    k = (k + 1) & 1023;
  }
}
BENCHMARK(BM_ContactTime2D);

// The calendar's cycle in a gas of monomers: pop the earliest event, refile its cluster's
// predictions (four events, as a monomer with a few neighbours has).
void BM_CalendarPopRefile(benchmark::State& state) {
  const auto clusters = static_cast<int>(state.range(0));
  Random rng(2, RandomPurpose::positions);
  EventCalendar calendar;
  calendar.reset(clusters);
  std::vector<Event> batch;
  auto refile = [&](int c, double now) {
    for (int k = 0; k < 4; ++k) batch.push_back({now + rng.uniform(), c, k, 0, 0, EventKind::collision});
    calendar.refile(c, batch);
    batch.clear();
  };
  for (int c = 0; c < clusters; ++c) refile(c, 0.0);
  for (auto _ : state) {
    const Event e = calendar.pop();
    refile(e.a, e.time);
  }
}
BENCHMARK(BM_CalendarPopRefile)->Arg(1 << 10)->Arg(1 << 16)->Arg(1 << 20);

}  // namespace

BENCHMARK_MAIN();
