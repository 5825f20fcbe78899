#pragma once
// The future event list of the event-driven engine: a binary min-heap of predicted events
// with lazy invalidation. Every event carries the stamps its clusters had when it was
// predicted; a cluster renews its stamp whenever its motion or membership changes, so a
// stale event is recognised in O(1) when it reaches the top and simply dropped.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "ballagg/engines/engine.hpp"

namespace ballagg {

struct Event {
  double time;
  std::int32_t a;             // collision: sphere i; wall, list rebuild: cluster
  std::int32_t b;             // collision: sphere j > i; wall: axis; list rebuild: 0
  std::uint64_t stamp_a;      // stamp of a's cluster (or of cluster a)
  std::uint64_t stamp_b;      // stamp of b's cluster (collisions only)
  EventKind kind;
};

// Total order: simultaneous events are handled in an order that depends only on what they
// are, never on when they were predicted, so runs are reproducible bit for bit.
inline bool later(const Event& x, const Event& y) {
  if (x.time != y.time) return x.time > y.time;
  if (x.kind != y.kind) return x.kind > y.kind;
  if (x.a != y.a) return x.a > y.a;
  return x.b > y.b;
}

class EventQueue {
 public:
  void push(const Event& e) {
    heap_.push_back(e);
    std::push_heap(heap_.begin(), heap_.end(), later);
  }
  bool empty() const { return heap_.empty(); }
  const Event& top() const { return heap_.front(); }
  void pop() {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    heap_.pop_back();
  }
  std::size_t size() const { return heap_.size(); }
  void clear() { heap_.clear(); }

  // Removes every event for which valid(e) is false: keeps memory proportional to the
  // live events when many predictions go stale far in the future.
  template <class Valid>
  void drop_stale(Valid&& valid) {
    std::erase_if(heap_, [&](const Event& e) { return !valid(e); });
    std::make_heap(heap_.begin(), heap_.end(), later);
  }

 private:
  std::vector<Event> heap_;
};

}  // namespace ballagg
