#pragma once
// Trajectory frames of a run kept in memory, and their comparison: shared by the tests of
// the snapshots (tests/run) and of the trajectory files (tests/io).
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/initial/initial_state.hpp"
#include "ballagg/io/frame_sink.hpp"
#include "ballagg/run/simulation.hpp"
#include "ballagg/run/snapshots.hpp"

namespace ballagg::testing {

// Keeps every frame in memory (shared with the test, the recorder owns the sink).
template <int D>
class MemorySink final : public FrameSink<D> {
 public:
  explicit MemorySink(std::shared_ptr<std::vector<Frame<D>>> frames) : frames_(std::move(frames)) {}
  void write(const Frame<D>& f) override { frames_->push_back(f); }
  void finish() override { finished = true; }
  std::uint64_t flush() override { return frames_->size(); }
  bool finished = false;

 private:
  std::shared_ptr<std::vector<Frame<D>>> frames_;
};

template <int D>
struct Recorded {
  std::vector<Frame<D>> frames;
  State<D> final_state;
  RunResult result;
};

// Runs `config` with an engine of its kind, frames every `every` kept in memory.
template <int D>
Recorded<D> run_with_snapshots(const Config& given, double every, StopCriteria stop = {},
                               std::optional<bool> mirror_at_walls = std::nullopt) {
  State<D> s = make_initial_state<D>(given);
  const Config c = resolve_defaults(given, s);
  auto frames = std::make_shared<std::vector<Frame<D>>>();
  std::vector<std::unique_ptr<FrameSink<D>>> sinks;
  sinks.push_back(std::make_unique<MemorySink<D>>(frames));
  SnapshotRecorder<D> recorder(every, std::move(sinks), mirror_at_walls.value_or(c.engine.kind == EngineKind::ts));
  Recorded<D> r{{}, {}, make_engine<D>(c)->run(s, stop, recorder)};
  r.frames = *frames;
  r.final_state = s;
  return r;
}

template <int D>
void expect_same_frame(const Frame<D>& a, const Frame<D>& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.cluster, b.cluster);
  EXPECT_EQ(a.image, b.image);
  for (int i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.position[i], b.position[i]) << "sphere " << i;
    EXPECT_EQ(a.velocity[i], b.velocity[i]) << "sphere " << i;
  }
}

}  // namespace ballagg::testing
