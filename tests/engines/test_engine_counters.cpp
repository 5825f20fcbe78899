// Each engine's counters: written into its checkpoint section field by field and read back
// unchanged, refused when cut short, and reported under their summary.json keys.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ballagg/engines/engine.hpp"
#include "ballagg/engines/event_driven/event_driven_counters.hpp"
#include "ballagg/engines/rigid_body/rigid_body_counters.hpp"
#include "ballagg/engines/time_stepping/ts_counters.hpp"

namespace {

using namespace ballagg;

template <class Counters>
Counters read_back(const Counters& saved) {
  ByteWriter w;
  saved.save(w);
  ByteReader r(w.bytes(), "counters");
  Counters read;
  read.restore(r);
  r.expect_end();
  return read;
}

template <class Counters>
std::string saved_bytes(const Counters& c) {
  ByteWriter w;
  c.save(w);
  return w.bytes();
}

std::vector<std::string> keys(const EngineCounts& counts) {
  std::vector<std::string> k;
  for (const EngineCount& c : counts) k.emplace_back(c.key);
  return k;
}

TEST(EngineCounters, EachEnginesCountersComeBackFromItsCheckpointSection) {
  RigidBodyCounters rb;
  rb.events = 1, rb.collisions = 2, rb.merges = 3, rb.bounces = 4, rb.wall_bounces = 5, rb.first_time_collisions = 6;
  rb.list_rebuilds = 7, rb.rebuilt_spheres = 8, rb.pair_predictions = 9, rb.queue_peak = 10;
  rb.fragmentations = 11, rb.contact_searches = 12, rb.advancement_steps = 13, rb.pose_evaluations = 14;
  const RigidBodyCounters rb_back = read_back(rb);
  EXPECT_EQ(rb_back.report(), rb.report());
  EXPECT_EQ(static_cast<const EngineCounters&>(rb_back), static_cast<const EngineCounters&>(rb));

  TimeSteppingCounters ts;
  ts.events = ts.steps = 21, ts.merges = 3, ts.minimisations = 4, ts.daha_iterations = 500, ts.placed_at_contact = 6;
  ts.link_rounds = 7, ts.rounds_exhausted = 8, ts.max_residual_overlap = 1.25e-4, ts.max_link_stretch = 0.0625;
  EXPECT_EQ(read_back(ts).report(true), ts.report(true));
  EXPECT_EQ(static_cast<const EngineCounters&>(read_back(ts)), static_cast<const EngineCounters&>(ts));
}

TEST(EngineCounters, ACounterSectionCutShortIsRefused) {
  RigidBodyCounters rb;
  const std::string bytes = saved_bytes(rb);
  ByteReader r(std::string_view(bytes).substr(0, bytes.size() - 1), "checkpoint of the rigid-body engine");
  EXPECT_THROW(rb.restore(r), CheckpointError);
}

TEST(EngineCounters, EachEngineReportsItsOwnCountersInSummaryOrder) {
  EXPECT_EQ(keys(EventDrivenCounters{}.report()),
            (std::vector<std::string>{"list_rebuilds", "rebuilt_spheres", "pair_predictions", "event_queue_peak"}));
  EXPECT_EQ(keys(RigidBodyCounters{}.report()),
            (std::vector<std::string>{"list_rebuilds", "rebuilt_spheres", "pair_predictions", "event_queue_peak",
                                      "first_time_collisions", "fragmentations", "contact_searches",
                                      "advancement_steps", "pose_evaluations"}));
  const std::vector<std::string> ts{"steps", "minimisations", "daha_iterations", "placed_at_contact", "link_rounds",
                                    "link_rounds_exhausted", "max_residual_overlap"};
  EXPECT_EQ(keys(TimeSteppingCounters{}.report(false)), ts);
  std::vector<std::string> with_links = ts;
  with_links.push_back("max_link_stretch");
  EXPECT_EQ(keys(TimeSteppingCounters{}.report(true)), with_links);
}

TEST(EngineCounters, ARunResultFindsACounterByItsKeyAndRefusesAnother) {
  TimeSteppingCounters ts;
  ts.steps = 31;
  ts.max_residual_overlap = 2e-4;
  RunResult r;
  r.engine_counts = ts.report(false);
  EXPECT_EQ(r.count("steps"), 31);
  EXPECT_EQ(r.measure("max_residual_overlap"), 2e-4);
  EXPECT_THROW(r.count("max_residual_overlap"), std::out_of_range);  // a double, not a count
  EXPECT_THROW(r.count("pair_predictions"), std::out_of_range);      // not a counter of ts
}

}  // namespace
