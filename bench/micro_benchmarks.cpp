// Micro-benchmarks of the engines' inner operations (Google Benchmark).
// Run: build/bin/ballagg_micro
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "ballagg/collision/contact_time.hpp"
#include "ballagg/core/random.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"
#include "ballagg/spatial/swept_box_grid.hpp"

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

// The swept boxes of a settling group of n clusters in 2D (monomers of radius 0.2 at the
// density of Vf 0.3, each flown 10 in a random direction, as in the long steps of a run of
// 10^7 discs at dt_factor 0.005): the boxes that may meet each box, through the grid
// (SweptBoxGrid) or by testing every pair, as a retreat does for a group below
// kPartnerGridClusters. Items: boxes.
std::vector<SweptBox<2>> settling_boxes(int n) {
  Random rng(3, RandomPurpose::positions);
  const double side = std::sqrt(n / 2.39);  // 2.39 discs per unit area at Vf 0.3, R = 0.2
  std::vector<SweptBox<2>> boxes;
  for (int k = 0; k < n; ++k) {
    const Vec<2> from(rng.uniform(0, side), rng.uniform(0, side));
    const double angle = rng.uniform(0, 6.283185307179586);
    const Vec<2> to = from + 10.0 * Vec<2>(std::cos(angle), std::sin(angle));
    const Vec<2> widen = Vec<2>::Constant(0.2 + 0.4);
    boxes.push_back({Vec<2>(from.cwiseMin(to) - widen), Vec<2>(from.cwiseMax(to) + widen)});
  }
  return boxes;
}

void BM_SweptBoxGrid(benchmark::State& state) {
  const std::vector<SweptBox<2>> boxes = settling_boxes(static_cast<int>(state.range(0)));
  const Box<2> box{1e6, Boundary::walls};
  for (auto _ : state) {
    const SweptBoxGrid<2> grid(box, boxes);
    std::int64_t candidates = 0;
    for (std::size_t k = 0; k < boxes.size(); ++k) grid.for_each_candidate(k, [&](std::int32_t) { ++candidates; });
    benchmark::DoNotOptimize(candidates);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SweptBoxGrid)->Arg(1000)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

void BM_SweptBoxesEveryPair(benchmark::State& state) {
  const std::vector<SweptBox<2>> boxes = settling_boxes(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    std::int64_t overlapping = 0;
    for (std::size_t k = 0; k < boxes.size(); ++k)
      for (std::size_t m = 0; m < boxes.size(); ++m)
        overlapping += (boxes[k].lo.array() <= boxes[m].hi.array()).all() && (boxes[m].lo.array() <= boxes[k].hi.array()).all();
    benchmark::DoNotOptimize(overlapping);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SweptBoxesEveryPair)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
