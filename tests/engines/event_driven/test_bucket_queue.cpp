// The bucketed queue of clusters behind the event calendar must give exactly the order of
// a plain priority queue, whatever its buckets: random updates, removals and pops are
// checked against a reference minimum, with many equal times (ties broken by key) and
// times before the current bucket (events predicted at the present instant).
#include <gtest/gtest.h>

#include <map>

#include "ballagg/core/random.hpp"
#include "ballagg/engines/event_driven/bucket_queue.hpp"

namespace ballagg {
namespace {

struct ByKey {
  bool operator()(int a, int b) const { return a < b; }
};

// The reference: the key with the least (time, key).
int reference_top(const std::map<int, double>& filed) {
  int best = -1;
  for (const auto& [k, t] : filed)
    if (best < 0 || t < filed.at(best)) best = k;
  return best;
}

void check_against_reference(int n_keys, int steps, double time_grain, std::uint64_t seed) {
  Random rng(seed, RandomPurpose::positions);
  BucketQueue<ByKey> queue{ByKey{}};
  queue.reset(n_keys);
  std::map<int, double> filed;
  double now = 0.0;
  // Times rounded to a grain make ties common; a few land before the present.
  auto draw = [&](double from) { return from + time_grain * std::floor(rng.uniform(-0.05, 3.0) / time_grain); };
  for (int k = 0; k < n_keys; ++k) {
    const double t = draw(now);
    queue.update(k, t);
    filed[k] = t;
  }
  for (int step = 0; step < steps && !filed.empty(); ++step) {
    ASSERT_EQ(queue.size(), filed.size());
    const int top = queue.top();
    ASSERT_EQ(top, reference_top(filed)) << "step " << step;
    now = std::max(now, filed[top]);
    const double u = rng.uniform();
    if (u < 0.05) {
      queue.remove(top);
      filed.erase(top);
    } else {
      const double t = draw(now);
      queue.update(top, t);
      filed[top] = t;
    }
    // Another key changes too, as a partner's prediction does.
    const int other = static_cast<int>(rng.uniform() * n_keys);
    if (rng.uniform() < 0.5) {
      const double t = draw(now);
      queue.update(other, t);
      filed[other] = t;
    } else if (rng.uniform() < 0.1) {
      queue.remove(other);
      filed.erase(other);
    }
  }
}

TEST(BucketQueue, PopsInTheOrderOfAPlainPriorityQueue) {
  check_against_reference(200, 20000, 1e-9, 1);
}

TEST(BucketQueue, BreaksTiesByTheCallersOrder) {
  check_against_reference(200, 20000, 0.25, 2);
}

TEST(BucketQueue, HandlesAllKeysAtOneTime) {
  BucketQueue<ByKey> queue{ByKey{}};
  queue.reset(1000);
  for (int k = 999; k >= 0; --k) queue.update(k, 1.5);
  for (int k = 0; k < 1000; ++k) {
    ASSERT_EQ(queue.top(), k);
    queue.remove(k);
  }
  EXPECT_TRUE(queue.empty());
}

}  // namespace
}  // namespace ballagg
