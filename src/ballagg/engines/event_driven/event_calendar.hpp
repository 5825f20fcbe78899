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
// the heap (pooled_lists.hpp), or only the earliest event of each cluster, in place (below);
// and a bucketed queue of clusters keyed by the earliest event of each (bucket_queue.hpp):
// repositioning a cluster after an event costs O(1) there, where a heap of clusters cost
// O(log M) scattered comparisons.
//
// A calendar may instead keep only each cluster's earliest event (CalendarKeeps::
// earliest_only, the one-event-per-particle calendar of Smallenburg's EDMD carried over
// to clusters). Most predictions go stale before they are due (a partner's motion changes
// first), so filing them all costs heap work and memory for nothing. A core that keeps the
// earliest only predicts a cluster afresh after every event filed under it: when it
// handles the event, and when the event turns out stale (CalendarDispatch calls its
// refill()). Every prediction left out comes after the one kept, so it is made again before
// it is due; predictions are pure functions of the motions (collision/prediction.hpp), so
// it is made again bit for bit, and the run handles the same events in the same order as
// with every event kept. A cluster then costs one 32-byte event, not a heap in the pool.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/pooled_lists.hpp"
#include "ballagg/engines/engine.hpp"
#include "ballagg/engines/event_driven/bucket_queue.hpp"
#include "ballagg/engines/event_driven/calendar_keeps.hpp"

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
// it to a multiple of 8). The kind goes into the top bits of stamp_a's word: stamps stay
// below kStampLimit (core/state.hpp), so they never reach those bits; a larger one is
// refused, never cut.
struct FiledEvent {
  static constexpr int kKindShift = 61;
  static constexpr std::uint64_t kStampLimit = std::uint64_t{1} << kKindShift;
  static_assert(kStampLimit == ballagg::kStampLimit, "the state's stamps must fit below the kind bits");

  FiledEvent() = default;
  explicit FiledEvent(const Event& e)
      : time(e.time), a(e.a), b(e.b),
        kind_and_stamp_a(static_cast<std::uint64_t>(e.kind) << kKindShift | e.stamp_a), stamp_b(e.stamp_b) {
    if (e.stamp_a >= kStampLimit || e.stamp_b >= kStampLimit)
      throw std::length_error("event calendar: a cluster stamp beyond 2^61");
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
  EventCalendar(const EventCalendar&) = delete;  // order_ points to this calendar
  EventCalendar& operator=(const EventCalendar&) = delete;

  // n_clusters clusters without events, keeping what `keeps` says of each one's events.
  void reset(int n_clusters, CalendarKeeps keeps = CalendarKeeps::every_event) {
    keeps_ = keeps;
    if (keeps_ == CalendarKeeps::every_event) {
      filed_.reset(n_clusters);
      std::vector<FiledEvent>().swap(earliest_);
    } else {
      filed_.reset(0);
      earliest_.assign(static_cast<std::size_t>(n_clusters), FiledEvent{});
    }
    order_.reset(n_clusters);
    stored_ = 0;
  }
  CalendarKeeps keeps() const { return keeps_; }

  // Replaces all events filed under cluster c (its stamp has changed) by `events`.
  void refile(int c, const std::vector<Event>& events) {
    if (keeps_ == CalendarKeeps::earliest_only) {
      forget(c);
      file(c, events);
      return;
    }
    stored_ -= filed_.size(c);
    filed_.assign(c, events.data(), events.size());
    stored_ += filed_.size(c);
    std::make_heap(filed_.begin(c), filed_.end(c), filed_later);
    reposition(c);
  }

  // Adds events to those filed under cluster c (its stamp has not changed).
  void file(int c, const std::vector<Event>& events) {
    if (keeps_ == CalendarKeeps::earliest_only) {
      if (events.empty()) return;
      const bool held = order_.contains(c);
      FiledEvent earliest = held ? earliest_[c] : FiledEvent(events.front());
      for (const Event& e : events) {
        const FiledEvent f(e);
        if (filed_later(earliest, f)) earliest = f;
      }
      earliest_[c] = earliest;
      stored_ += held ? 0 : 1;
      order_.update(c, earliest.time);
      return;
    }
    for (const Event& e : events) {
      filed_.push_back(c, FiledEvent(e));
      std::push_heap(filed_.begin(c), filed_.end(c), filed_later);
    }
    stored_ += events.size();
    reposition(c);
  }

  // Drops every event of cluster c and releases its memory (c was merged away).
  void forget(int c) {
    if (keeps_ == CalendarKeeps::earliest_only) {
      if (order_.contains(c)) --stored_;
      order_.remove(c);
      return;
    }
    stored_ -= filed_.size(c);
    filed_.release(c);
    reposition(c);
  }

  bool empty() const { return order_.empty(); }
  std::size_t size() const { return stored_; }
  // The time of the earliest event filed (possibly stale), or +inf.
  double earliest_time() {
    return order_.empty() ? std::numeric_limits<double>::infinity() : front(order_.top()).time;
  }

  // Removes and returns the earliest event (possibly stale). Requires !empty().
  Event pop() {
    const int c = order_.top();
    last_popped_from_ = c;
    --stored_;
    if (keeps_ == CalendarKeeps::earliest_only) {
      order_.remove(c);
      return earliest_[c].event();
    }
    std::pop_heap(filed_.begin(c), filed_.end(c), filed_later);
    const Event e = filed_.end(c)[-1].event();
    filed_.pop_back(c);
    reposition(c);
    return e;
  }
  // The cluster the last pop() took its event from.
  int last_popped_from() const { return last_popped_from_; }

  // Files the event the last pop() returned again, where it was: the calendar then holds
  // the same events as before that pop, and gives them in the same order (the order is
  // total). Nothing may have been filed or dropped since.
  void put_back(const Event& e) { file(last_popped_from_, {e}); }

  // Checkpoints: every cluster's events (stale ones too: the event-queue peak counts them).
  // restore() into a calendar reset() to the same number of clusters; check(e) throws for
  // an event whose ids do not fit the state. The queue of clusters is rebuilt: its layout
  // affects the speed only, never which event comes first (bucket_queue.hpp).
  void save(ByteWriter& w) const {
    for (int c = 0; c < static_cast<int>(order_size()); ++c) {
      const std::span<const FiledEvent> events = filed(c);
      w.put<std::uint32_t>(static_cast<std::uint32_t>(events.size()));
      for (const FiledEvent& filed : events) {
        // Field by field, as an Event: the format keeps its layout.
        w.put(filed.time);
        w.put(filed.a);
        w.put(filed.b);
        w.put(filed.kind_and_stamp_a & (FiledEvent::kStampLimit - 1));
        w.put(filed.stamp_b);
        w.put(filed.kind());
      }
    }
  }
  // A calendar that keeps the earliest event only keeps the earliest of a cluster's saved
  // ones (what it would have kept of them). The format also holds refill markers: a copy of
  // an event, its second stamp kMarkerBit + the cluster it is filed under. A marker is read
  // as its copied event with stamps 0, which no cluster has: found stale when due, it has
  // its cluster predicted again, which is what a marker stands for.
  template <class Check>
  void restore(ByteReader& r, Check&& check) {
    static constexpr std::uint64_t kMarkerBit = std::uint64_t{1} << 63;
    stored_ = 0;
    std::vector<Event> events;
    for (int c = 0; c < static_cast<int>(order_size()); ++c) {
      events.clear();
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
        if (e.stamp_b >= kMarkerBit) {
          if (e.stamp_b - kMarkerBit != static_cast<std::uint64_t>(c)) r.fail("a refill marker filed under another cluster");
          e.stamp_a = 0;
          e.stamp_b = 0;
        }
        if (e.stamp_b >= FiledEvent::kStampLimit) r.fail("event stamp beyond 2^61");
        check(e);
        events.push_back(e);
      }
      if (keeps_ == CalendarKeeps::earliest_only) {
        file(c, events);
        continue;
      }
      for (const Event& e : events) filed_.push_back(c, FiledEvent(e));
      if (!std::is_heap(filed_.begin(c), filed_.end(c), filed_later)) r.fail("a cluster's events out of order");
      stored_ += n;
      reposition(c);
    }
  }

 private:
  using Filed = PooledLists<FiledEvent>;

  // Orders clusters whose earliest events are simultaneous by those events.
  struct FrontOrder {
    const EventCalendar* calendar;
    bool operator()(int x, int y) const { return filed_later(calendar->front(y), calendar->front(x)); }
  };

  // Cluster c's earliest event. Requires one.
  const FiledEvent& front(int c) const {
    return keeps_ == CalendarKeeps::earliest_only ? earliest_[c] : filed_.front(c);
  }
  // Cluster c's events as stored (a heap, or the earliest alone).
  std::span<const FiledEvent> filed(int c) const {
    if (keeps_ == CalendarKeeps::every_event) return {filed_.begin(c), filed_.size(c)};
    if (!order_.contains(c)) return {};
    return {&earliest_[c], 1};
  }
  std::size_t order_size() const {
    return keeps_ == CalendarKeeps::every_event ? static_cast<std::size_t>(filed_.owners()) : earliest_.size();
  }

  // Refiles cluster c in the queue of clusters after its earliest event changed (or vanished).
  void reposition(int c) {
    if (filed_.empty(c)) order_.remove(c);
    else order_.update(c, filed_.front(c).time);
  }

  CalendarKeeps keeps_ = CalendarKeeps::every_event;
  // every_event: per cluster, a binary heap (earliest on top) of 32-byte events in a pool
  // of blocks (pooled_lists.hpp); a cluster costs an 8-byte handle and its events, and a
  // dead one no events. earliest_only: per cluster, its earliest event, in place.
  Filed filed_;
  std::vector<FiledEvent> earliest_;
  BucketQueue<FrontOrder> order_{FrontOrder{this}};  // clusters with events
  std::size_t stored_ = 0;
  int last_popped_from_ = 0;
};

}  // namespace ballagg
