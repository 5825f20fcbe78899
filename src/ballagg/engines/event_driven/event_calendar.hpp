#pragma once
// The future event list of the event-driven engine.
//
// Every event is filed under the cluster whose prediction produced it, and every such event
// involves that cluster. When the cluster's motion or membership changes, its stamp renews
// and all events filed under it are stale at once: the calendar simply drops its list and
// files the new predictions. Stale events survive only where a *partner* changed; they are
// recognised by their stamps when they reach the top (lazy invalidation).
//
// Layout: one small binary heap of events per cluster, kept in a pool of blocks sized to
// the heap (pooled_lists.hpp), and a bucketed queue of clusters
// keyed by the earliest event of each (bucket_queue.hpp): repositioning a cluster after
// an event costs O(1) there, where a heap of clusters cost O(log M) scattered comparisons.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/pooled_lists.hpp"
#include "ballagg/engines/engine.hpp"
#include "ballagg/engines/event_driven/bucket_queue.hpp"

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

// An event as the calendar stores it: 32 bytes, where an Event takes 40 (its kind byte pads
// it to a multiple of 8). The kind goes into the top bits of stamp_a's word: stamps count
// up from 1 (State::new_stamp), so they never reach those bits (2^61 renewals would take a
// run renewing a billion stamps a second 73 years); a larger one is refused, never cut.
struct FiledEvent {
  static constexpr int kKindShift = 61;
  static constexpr std::uint64_t kStampLimit = std::uint64_t{1} << kKindShift;

  FiledEvent() = default;
  explicit FiledEvent(const Event& e)
      : time(e.time), a(e.a), b(e.b),
        kind_and_stamp_a(static_cast<std::uint64_t>(e.kind) << kKindShift | e.stamp_a), stamp_b(e.stamp_b) {
    if (e.stamp_a >= kStampLimit) throw std::length_error("event calendar: a cluster stamp beyond 2^61");
  }
  Event event() const { return {time, a, b, kind_and_stamp_a & (kStampLimit - 1), stamp_b, kind()}; }
  EventKind kind() const { return static_cast<EventKind>(kind_and_stamp_a >> kKindShift); }

  double time;
  std::int32_t a;
  std::int32_t b;
  std::uint64_t kind_and_stamp_a;
  std::uint64_t stamp_b;
};
static_assert(sizeof(FiledEvent) == 32 && std::is_trivially_copyable_v<FiledEvent>);
static_assert(static_cast<int>(EventKind::contact_search) < 8, "the kind takes the top 3 bits of a stamp word");

// The same order as later(Event, Event): the kind sits above the stamp's bits.
inline bool filed_later(const FiledEvent& x, const FiledEvent& y) {
  if (x.time != y.time) return x.time > y.time;
  const std::uint64_t kx = x.kind_and_stamp_a >> FiledEvent::kKindShift;
  const std::uint64_t ky = y.kind_and_stamp_a >> FiledEvent::kKindShift;
  if (kx != ky) return kx > ky;
  if (x.a != y.a) return x.a > y.a;
  return x.b > y.b;
}

class EventCalendar {
 public:
  EventCalendar() = default;
  EventCalendar(const EventCalendar&) = delete;  // order_ points into filed_
  EventCalendar& operator=(const EventCalendar&) = delete;

  void reset(int n_clusters) {
    filed_.reset(n_clusters);
    order_.reset(n_clusters);
    stored_ = 0;
  }

  // Replaces all events filed under cluster c (its stamp has changed) by `events`.
  void refile(int c, const std::vector<Event>& events) {
    stored_ -= filed_.size(c);
    filed_.assign(c, events.data(), events.size());
    stored_ += events.size();
    std::make_heap(filed_.begin(c), filed_.end(c), filed_later);
    reposition(c);
  }

  // Adds events to those filed under cluster c (its stamp has not changed).
  void file(int c, const std::vector<Event>& events) {
    for (const Event& e : events) {
      filed_.push_back(c, FiledEvent(e));
      std::push_heap(filed_.begin(c), filed_.end(c), filed_later);
    }
    stored_ += events.size();
    reposition(c);
  }

  // Drops every event of cluster c and releases its memory (c was merged away).
  void forget(int c) {
    stored_ -= filed_.size(c);
    filed_.release(c);
    reposition(c);
  }

  bool empty() const { return order_.empty(); }
  std::size_t size() const { return stored_; }
  // The time of the earliest event filed (possibly stale), or +inf.
  double earliest_time() {
    return order_.empty() ? std::numeric_limits<double>::infinity() : filed_.front(order_.top()).time;
  }

  // Pops events until one passes `valid` (stale ones are dropped) and returns it.
  template <class Valid>
  std::optional<Event> pop_valid(Valid&& valid) {
    while (!empty()) {
      const Event e = pop();
      if (valid(e)) return e;
    }
    return std::nullopt;
  }

  // Removes and returns the earliest event (possibly stale). Requires !empty().
  Event pop() {
    const int c = order_.top();
    last_popped_from_ = c;
    std::pop_heap(filed_.begin(c), filed_.end(c), filed_later);
    const Event e = filed_.end(c)[-1].event();
    filed_.pop_back(c);
    --stored_;
    reposition(c);
    return e;
  }

  // Files the event the last pop() returned again, where it was: the calendar then holds
  // the same events as before that pop, and gives them in the same order (the order is
  // total). Nothing may have been filed or dropped since.
  void put_back(const Event& e) {
    const int c = last_popped_from_;
    filed_.push_back(c, FiledEvent(e));
    std::push_heap(filed_.begin(c), filed_.end(c), filed_later);
    ++stored_;
    reposition(c);
  }

  // Checkpoints: every cluster's events (stale ones too: the event-queue peak counts them).
  // restore() into a calendar reset() to the same number of clusters; check(e) throws for
  // an event whose ids do not fit the state. The queue of clusters is rebuilt: its layout
  // affects the speed only, never which event comes first (bucket_queue.hpp).
  void save(ByteWriter& w) const {
    for (int c = 0; c < filed_.owners(); ++c) {
      w.put<std::uint32_t>(filed_.size(c));
      for (const FiledEvent* filed = filed_.begin(c); filed != filed_.end(c); ++filed) {
        const Event e = filed->event();  // field by field, as an Event: the format keeps its layout
        w.put(e.time);
        w.put(e.a);
        w.put(e.b);
        w.put(e.stamp_a);
        w.put(e.stamp_b);
        w.put(e.kind);
      }
    }
  }
  template <class Check>
  void restore(ByteReader& r, Check&& check) {
    stored_ = 0;
    for (int c = 0; c < filed_.owners(); ++c) {
      filed_.clear(c);
      const auto n = r.get<std::uint32_t>("event count");
      for (std::uint32_t k = 0; k < n; ++k) {
        Event e;
        e.time = r.get<double>("event time");
        e.a = r.get<std::int32_t>("event");
        e.b = r.get<std::int32_t>("event");
        e.stamp_a = r.get<std::uint64_t>("event stamp");
        e.stamp_b = r.get<std::uint64_t>("event stamp");
        e.kind = r.get<EventKind>("event kind");
        if (!std::isfinite(e.time)) r.fail("event at a time that is not finite");
        if (e.stamp_a >= FiledEvent::kStampLimit) r.fail("event stamp beyond 2^61");
        check(e);
        filed_.push_back(c, FiledEvent(e));
      }
      if (!std::is_heap(filed_.begin(c), filed_.end(c), filed_later)) r.fail("a cluster's events out of order");
      stored_ += n;
      reposition(c);
    }
  }

 private:
  using Filed = PooledLists<FiledEvent>;

  // Orders clusters whose earliest events are simultaneous by those events.
  struct FrontOrder {
    const Filed* filed;
    bool operator()(int x, int y) const { return filed_later(filed->front(y), filed->front(x)); }
  };

  // Refiles cluster c in the queue of clusters after its earliest event changed (or vanished).
  void reposition(int c) {
    if (filed_.empty(c)) order_.remove(c);
    else order_.update(c, filed_.front(c).time);
  }

  // Per cluster: a binary heap (earliest on top) of 32-byte events in a pool of blocks
  // (pooled_lists.hpp). A cluster costs an 8-byte handle and its events: dead clusters cost
  // no events, and a monomer with one or two events uses a block of one or two.
  Filed filed_;
  BucketQueue<FrontOrder> order_{FrontOrder{&filed_}};  // clusters with events
  std::size_t stored_ = 0;
  int last_popped_from_ = 0;
};

}  // namespace ballagg
