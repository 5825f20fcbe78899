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
//
// A calendar may keep only the earliest few events of each cluster (keep_at_most(k), the
// one-event-per-particle idea of Smallenburg's EDMD carried over to clusters). Most filed
// predictions go stale before they are due (a partner's motion changes first), so filing
// them all costs heap work and memory for nothing. What is left out is stood for by one
// refill marker placed in the order just after the earliest event left out: every event
// before that one, the cluster's kept ones included, comes first, and nothing comes
// between. When the marker is due and the cluster's stamp is unchanged, its core predicts
// the cluster again (CalendarDispatch). Predictions are pure functions of the motions
// (collision/prediction.hpp), so the events filed again are bit for bit the ones left out,
// and the run handles the same events in the same order as with every event kept. Each
// refill is followed by the event it stood just after, so refills cannot go round.
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
// it to a multiple of 8). The kind goes into the top bits of stamp_a's word: stamps stay
// below kStampLimit (core/state.hpp), so they never reach those bits; a larger one is
// refused, never cut.
//
// A refill marker of cluster c is a copy of the earliest event left out with its second
// stamp replaced by kMarkerBit | c, and its first by c's stamp: ordered as that event,
// then after it (filed_later). Read back (event()) it is an Event of kind refill, a = c.
struct FiledEvent {
  static constexpr int kKindShift = 61;
  static constexpr std::uint64_t kStampLimit = std::uint64_t{1} << kKindShift;
  static_assert(kStampLimit == ballagg::kStampLimit, "the state's stamps must fit below the kind bits");
  static constexpr std::uint64_t kMarkerBit = std::uint64_t{1} << 63;

  FiledEvent() = default;
  explicit FiledEvent(const Event& e)
      : time(e.time), a(e.a), b(e.b),
        kind_and_stamp_a(static_cast<std::uint64_t>(e.kind) << kKindShift | e.stamp_a), stamp_b(e.stamp_b) {
    if (e.stamp_a >= kStampLimit || e.stamp_b >= kStampLimit)
      throw std::length_error("event calendar: a cluster stamp beyond 2^61");
  }
  // The marker of cluster c (whose stamp is `stamp`) standing just after `left_out`.
  static FiledEvent marker(const FiledEvent& left_out, int c, std::uint64_t stamp) {
    FiledEvent m = left_out;
    m.kind_and_stamp_a = (left_out.kind_and_stamp_a & ~(kStampLimit - 1)) | stamp;
    m.stamp_b = kMarkerBit | static_cast<std::uint32_t>(c);
    return m;
  }
  bool is_marker() const { return stamp_b >= kMarkerBit; }
  Event event() const {
    const std::uint64_t stamp = kind_and_stamp_a & (kStampLimit - 1);
    if (is_marker()) return {time, static_cast<std::int32_t>(stamp_b & ~kMarkerBit), 0, stamp, 0, EventKind::refill};
    return {time, a, b, stamp, stamp_b, kind()};
  }
  EventKind kind() const { return static_cast<EventKind>(kind_and_stamp_a >> kKindShift); }

  double time;
  std::int32_t a;
  std::int32_t b;
  std::uint64_t kind_and_stamp_a;
  std::uint64_t stamp_b;
};
static_assert(sizeof(FiledEvent) == 32 && std::is_trivially_copyable_v<FiledEvent>);
static_assert(static_cast<int>(EventKind::contact_search) < 8, "the kind takes the top 3 bits of a stamp word");

// The same order as later(Event, Event): the kind sits above the stamp's bits. A marker
// comes just after the event it copies (and after a marker of a lower cluster copying the
// same event).
inline bool filed_later(const FiledEvent& x, const FiledEvent& y) {
  if (x.time != y.time) return x.time > y.time;
  const std::uint64_t kx = x.kind_and_stamp_a >> FiledEvent::kKindShift;
  const std::uint64_t ky = y.kind_and_stamp_a >> FiledEvent::kKindShift;
  if (kx != ky) return kx > ky;
  if (x.a != y.a) return x.a > y.a;
  if (x.b != y.b) return x.b > y.b;
  if (x.is_marker() != y.is_marker()) return x.is_marker();
  return x.is_marker() && x.stamp_b > y.stamp_b;
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

  // From now on, at most `k` events (k >= 1) are kept per cluster, and a refill marker
  // stands for the rest; 0 keeps every event. A core that sets it handles refill markers
  // (CalendarDispatch) and predicts purely.
  void keep_at_most(int k) { kept_ = k; }

  // Replaces all events filed under cluster c (its stamp has changed) by `events`; `stamp`
  // is c's stamp (for a refill marker).
  void refile(int c, const std::vector<Event>& events, std::uint64_t stamp = 0) {
    stored_ -= filed_.size(c);
    if (kept_ > 0 && events.size() > static_cast<std::size_t>(kept_)) {
      candidates_.clear();
      for (const Event& e : events) candidates_.emplace_back(e);
      keep_earliest(c, nullptr, stamp);
    } else {
      filed_.assign(c, events.data(), events.size());
    }
    stored_ += filed_.size(c);
    std::make_heap(filed_.begin(c), filed_.end(c), filed_later);
    reposition(c);
  }

  // Adds events to those filed under cluster c (its stamp has not changed, and is `stamp`).
  void file(int c, const std::vector<Event>& events, std::uint64_t stamp = 0) {
    if (kept_ > 0 && filed_.size(c) + events.size() > static_cast<std::size_t>(kept_)) {
      refile_with(c, events, stamp);
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
        // Field by field, as an Event: the format keeps its layout. A marker is saved as
        // the copy it is (its second stamp carries the marker bit and its cluster).
        w.put(filed->time);
        w.put(filed->a);
        w.put(filed->b);
        w.put(filed->kind_and_stamp_a & (FiledEvent::kStampLimit - 1));
        w.put(filed->stamp_b);
        w.put(filed->kind());
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
        const bool marker = e.stamp_b >= FiledEvent::kMarkerBit;
        if (marker) {
          // The copied event's kind and ids are checked as an event's, its cluster as a marker's.
          if (e.stamp_b - FiledEvent::kMarkerBit > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
            r.fail("a refill marker that names no cluster");
          check(Event{e.time, e.a, e.b, e.stamp_a, 0, e.kind});
          check(Event{e.time, static_cast<std::int32_t>(e.stamp_b - FiledEvent::kMarkerBit), 0, e.stamp_a, 0,
                      EventKind::refill});
          const std::uint64_t copied_stamp_b = e.stamp_b;
          e.stamp_b = 0;
          FiledEvent filed(e);
          filed.stamp_b = copied_stamp_b;
          filed_.push_back(c, filed);
        } else {
          if (e.stamp_b >= FiledEvent::kStampLimit) r.fail("event stamp beyond 2^61");
          check(e);
          filed_.push_back(c, FiledEvent(e));
        }
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

  // file() beyond the bound: c's events so far (a marker among them stands for events
  // from its time on) and the new ones, cut again to the earliest kept_.
  void refile_with(int c, const std::vector<Event>& events, std::uint64_t stamp) {
    std::optional<FiledEvent> marker;  // a cluster holds at most one
    candidates_.clear();
    for (const FiledEvent* f = filed_.begin(c); f != filed_.end(c); ++f) {
      if (f->is_marker()) marker = *f;
      else candidates_.push_back(*f);
    }
    for (const Event& e : events) candidates_.emplace_back(e);
    stored_ -= filed_.size(c);
    if (candidates_.size() > static_cast<std::size_t>(kept_)) {
      keep_earliest(c, marker ? &*marker : nullptr, stamp);
    } else {
      if (marker) candidates_.push_back(*marker);
      filed_.assign(c, candidates_.data(), candidates_.size());
    }
    stored_ += filed_.size(c);
    std::make_heap(filed_.begin(c), filed_.end(c), filed_later);
    reposition(c);
  }

  // Files under c the kept_ earliest of candidates_ (more than kept_ of them, no marker
  // among them) and a refill marker just after the earliest one left out, or `marker` (c's
  // marker so far) if that comes sooner. Not yet a heap.
  void keep_earliest(int c, const FiledEvent* marker, std::uint64_t stamp) {
    const auto first_left_out = candidates_.begin() + kept_;
    std::nth_element(candidates_.begin(), first_left_out, candidates_.end(),
                     [](const FiledEvent& x, const FiledEvent& y) { return filed_later(y, x); });
    const FiledEvent fresh = FiledEvent::marker(*first_left_out, c, stamp);
    *first_left_out = marker != nullptr && filed_later(fresh, *marker) ? *marker : fresh;
    filed_.assign(c, candidates_.data(), static_cast<std::size_t>(kept_) + 1);
  }

  // Per cluster: a binary heap (earliest on top) of 32-byte events in a pool of blocks
  // (pooled_lists.hpp). A cluster costs an 8-byte handle and its events: dead clusters cost
  // no events, and a monomer with one or two events uses a block of one or two.
  Filed filed_;
  BucketQueue<FrontOrder> order_{FrontOrder{&filed_}};  // clusters with events
  std::size_t stored_ = 0;
  int last_popped_from_ = 0;
  int kept_ = 0;                     // events kept per cluster (0: all)
  std::vector<FiledEvent> candidates_;  // scratch of refile() and file() under a bound
};

}  // namespace ballagg
