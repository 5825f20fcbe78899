// The observers of a run share one checkpoint offer: only those that asked for it
// (checkpoint_due) are handed the engine's state, so that none gathers bytes it does not
// use (at 10^6 spheres a few hundred MB).
#include <string>

#include <gtest/gtest.h>

#include "ballagg/run/observer_list.hpp"

namespace ballagg {
namespace {

class Asking final : public RunObserver<2> {
 public:
  explicit Asking(bool due) : due_(due) {}
  bool checkpoint_due() override { return due_; }
  void on_checkpoint(const State<2>&, const EngineCounters&, const std::string& engine_state) override {
    received = engine_state;
    ++calls;
  }
  std::string received;
  int calls = 0;

 private:
  bool due_;
};

TEST(ObserverList, HandsACheckpointOnlyToTheObserversThatAskedForIt) {
  Asking due(true), not_due(false);
  ObserverList<2> list;
  list.add(&not_due);
  list.add(&due);
  ASSERT_TRUE(list.checkpoint_due());
  int saves = 0;
  const State<2> s;
  list.on_checkpoint_stream(s, EngineCounters{}, [&](ByteWriter& w) {
    ++saves;
    w.put_string("engine");
  });
  EXPECT_EQ(saves, 1);
  EXPECT_EQ(due.calls, 1);
  EXPECT_EQ(not_due.calls, 0);
  ByteWriter expected;
  expected.put_string("engine");
  EXPECT_EQ(due.received, expected.bytes());
}

}  // namespace
}  // namespace ballagg
