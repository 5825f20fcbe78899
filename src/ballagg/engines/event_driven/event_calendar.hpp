#pragma once
// The future event list of the event-driven engine.
//
// Every event is filed under the cluster whose prediction produced it, and every such event
// involves that cluster. When the cluster's motion or membership changes, its stamp renews
// and all events filed under it are stale at once: the calendar simply drops its list and
// files the new predictions. Stale events survive only where a *partner* changed; they are
// recognised by their stamps when they reach the top (lazy invalidation).
//
// Layout: one small binary heap of events per cluster, and a bucketed queue of clusters
// keyed by the earliest event of each (bucket_queue.hpp): repositioning a cluster after
// an event costs O(1) there, where a heap of clusters cost O(log M) scattered comparisons.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/small_vector.hpp"
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

class EventCalendar {
  // A monomer of a gas has one or two events filed at a time: three fit in place (two
  // cache lines), so reading a cluster's earliest event is one memory access, not two.
  using Filed = SmallVector<Event, 3, 64>;

 public:
  EventCalendar() = default;
  EventCalendar(const EventCalendar&) = delete;  // order_ points into filed_
  EventCalendar& operator=(const EventCalendar&) = delete;

  void reset(int n_clusters) {
    filed_.assign(n_clusters, {});
    order_.reset(n_clusters);
    stored_ = 0;
  }

  // Replaces all events filed under cluster c (its stamp has changed) by `events`.
  void refile(int c, const std::vector<Event>& events) {
    Filed& mine = filed_[c];
    stored_ -= mine.size();
    mine.clear();
    for (const Event& e : events) mine.push_back(e);
    stored_ += mine.size();
    std::make_heap(mine.begin(), mine.end(), later);
    reposition(c);
  }

  // Adds events to those filed under cluster c (its stamp has not changed).
  void file(int c, const std::vector<Event>& events) {
    Filed& mine = filed_[c];
    for (const Event& e : events) {
      mine.push_back(e);
      std::push_heap(mine.begin(), mine.end(), later);
    }
    stored_ += events.size();
    reposition(c);
  }

  // Drops every event of cluster c and releases its memory (c was merged away).
  void forget(int c) {
    stored_ -= filed_[c].size();
    filed_[c] = Filed();
    reposition(c);
  }

  bool empty() const { return order_.empty(); }
  std::size_t size() const { return stored_; }
  // The time of the earliest event filed (possibly stale), or +inf.
  double earliest_time() {
    return order_.empty() ? std::numeric_limits<double>::infinity() : filed_[order_.top()].front().time;
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
    Filed& mine = filed_[c];
    std::pop_heap(mine.begin(), mine.end(), later);
    const Event e = mine.back();
    mine.pop_back();
    --stored_;
    reposition(c);
    return e;
  }

  // Files the event the last pop() returned again, where it was: the calendar then holds
  // the same events as before that pop, and gives them in the same order (the order is
  // total). Nothing may have been filed or dropped since.
  void put_back(const Event& e) {
    Filed& mine = filed_[last_popped_from_];
    mine.push_back(e);
    std::push_heap(mine.begin(), mine.end(), later);
    ++stored_;
    reposition(last_popped_from_);
  }

  // Checkpoints: every cluster's events (stale ones too: the event-queue peak counts them).
  // restore() into a calendar reset() to the same number of clusters; check(e) throws for
  // an event whose ids do not fit the state. The queue of clusters is rebuilt: its layout
  // affects the speed only, never which event comes first (bucket_queue.hpp).
  void save(ByteWriter& w) const {
    for (const Filed& mine : filed_) {
      w.put<std::uint32_t>(static_cast<std::uint32_t>(mine.size()));
      for (const Event& e : mine) {  // field by field: the struct's padding is not data
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
    for (std::size_t c = 0; c < filed_.size(); ++c) {
      Filed& mine = filed_[c];
      mine.clear();
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
        check(e);
        mine.push_back(e);
      }
      if (!std::is_heap(mine.begin(), mine.end(), later)) r.fail("a cluster's events out of order");
      stored_ += mine.size();
      reposition(static_cast<int>(c));
    }
  }

 private:
  // Orders clusters whose earliest events are simultaneous by those events.
  struct FrontOrder {
    const std::vector<Filed>* filed;
    bool operator()(int x, int y) const { return later((*filed)[y].front(), (*filed)[x].front()); }
  };

  // Refiles cluster c in the queue of clusters after its earliest event changed (or vanished).
  void reposition(int c) {
    if (filed_[c].empty()) order_.remove(c);
    else order_.update(c, filed_[c].front().time);
  }

  std::vector<Filed> filed_;  // per cluster: a binary heap (earliest on top)
  BucketQueue<FrontOrder> order_{FrontOrder{&filed_}};  // clusters with events
  std::size_t stored_ = 0;
  int last_popped_from_ = 0;
};

}  // namespace ballagg
