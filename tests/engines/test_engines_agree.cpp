// The fast engine against the paper's O(N^2) reference: on small systems both must follow
// the same merge sequence and end in bit-identical states (docs/engines.md explains why
// the predictions are bit-identical).
#include <gtest/gtest.h>

#include "ballagg/io/state_csv.hpp"
#include "support.hpp"

namespace ballagg {
namespace {
using testing::Recorder;
using testing::run_engine;

struct Case {
  int dimension;
  Boundary boundary;
  CollisionOutcome outcome;
  int n;
  double volume_fraction;
  std::uint64_t seed;
  double restitution = 0.8;
  double bounce_until = 15.0;
};

template <int D>
void expect_same_history(const Case& k) {
  Config c = testing::small_config(D, k.n, k.volume_fraction, k.boundary, k.seed);
  StopCriteria stop;
  if (k.outcome == CollisionOutcome::bounce) stop.time = k.bounce_until;
  const CollisionSettings law{k.outcome, k.restitution, 0.0};
  State<D> fast = make_initial_state<D>(c), naive = make_initial_state<D>(c);
  Recorder<D> fast_events, naive_events;
  run_engine(fast, "ed", law, stop, &fast_events);
  run_engine(naive, "ed-naive", law, stop, &naive_events);
  const auto a = fast_events.of_kind(EventKind::collision), b = naive_events.of_kind(EventKind::collision);
  ASSERT_GT(a.size(), 20u);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t e = 0; e < a.size(); ++e) {
    ASSERT_EQ(a[e].time, b[e].time) << "collision " << e;
    ASSERT_EQ(a[e].sphere_i, b[e].sphere_i) << "collision " << e;
    ASSERT_EQ(a[e].sphere_j, b[e].sphere_j) << "collision " << e;
    ASSERT_EQ(a[e].merges, b[e].merges) << "collision " << e;
  }
  EXPECT_EQ(fast_events.of_kind(EventKind::wall).size(), naive_events.of_kind(EventKind::wall).size());
  EXPECT_EQ(state_csv_text(fast), state_csv_text(naive));
}

TEST(EnginesAgree, SameMergeSequence2DWalls) { expect_same_history<2>({2, Boundary::walls, CollisionOutcome::stick, 150, 0.2, 1}); }
TEST(EnginesAgree, SameMergeSequence2DPeriodic) { expect_same_history<2>({2, Boundary::periodic, CollisionOutcome::stick, 150, 0.1, 2}); }
TEST(EnginesAgree, SameMergeSequence3DWalls) { expect_same_history<3>({3, Boundary::walls, CollisionOutcome::stick, 150, 0.15, 3}); }
TEST(EnginesAgree, SameMergeSequence3DPeriodic) { expect_same_history<3>({3, Boundary::periodic, CollisionOutcome::stick, 150, 0.1, 4}); }
TEST(EnginesAgree, SameBounceSequence2D) { expect_same_history<2>({2, Boundary::walls, CollisionOutcome::bounce, 80, 0.2, 5}); }
TEST(EnginesAgree, SameBounceSequence3DPeriodic) { expect_same_history<3>({3, Boundary::periodic, CollisionOutcome::bounce, 80, 0.2, 6}); }
// An elastic gas keeps its speeds: spheres turn back again and again, each time from
// wherever its lists' drift has carried it (engines/event_driven/neighbor_keeper.hpp).
TEST(EnginesAgree, SameElasticSequence2DWalls) {
  expect_same_history<2>({2, Boundary::walls, CollisionOutcome::bounce, 200, 0.3, 7, 1.0, 40.0});
}
TEST(EnginesAgree, SameElasticSequence3DPeriodic) {
  expect_same_history<3>({3, Boundary::periodic, CollisionOutcome::bounce, 120, 0.3, 8, 1.0, 10.0});
}

}  // namespace
}  // namespace ballagg
