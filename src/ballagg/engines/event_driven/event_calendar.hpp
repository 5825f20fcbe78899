#pragma once
// The future event list of the event-driven engine.
//
// Every event is filed under the cluster whose prediction produced it, and every such event
// involves that cluster. When the cluster's motion or membership changes, its stamp renews
// and all events filed under it are stale at once: the calendar simply drops its list and
// files the new predictions. Stale events survive only where a *partner* changed; they are
// recognised by their stamps when they reach the top (lazy invalidation).
//
// Layout: one small binary heap of events per cluster, and an indexed 4-ary heap of
// clusters keyed by the earliest event of each (4-ary: half the depth of a binary heap
// for the same number of comparisons per level that fit one cache line). Popping costs O(log k + log M) for k events
// of a cluster and M clusters, on small, cache-friendly arrays, instead of O(log Q) on one
// large heap of every prediction ever made.
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

class EventCalendar {
 public:
  void reset(int n_clusters) {
    filed_.assign(n_clusters, {});
    slot_.assign(n_clusters, -1);
    order_.clear();
    stored_ = 0;
  }

  // Replaces all events filed under cluster c (its stamp has changed) by `events`.
  void refile(int c, std::vector<Event>&& events) {
    std::vector<Event>& mine = filed_[c];
    stored_ += events.size();
    stored_ -= mine.size();
    mine.swap(events);
    events.clear();
    std::make_heap(mine.begin(), mine.end(), later);
    reposition(c);
  }

  // Adds events to those filed under cluster c (its stamp has not changed).
  void file(int c, const std::vector<Event>& events) {
    std::vector<Event>& mine = filed_[c];
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
    std::vector<Event>().swap(filed_[c]);
    reposition(c);
  }

  bool empty() const { return order_.empty(); }
  std::size_t size() const { return stored_; }

  // Removes and returns the earliest event (possibly stale). Requires !empty().
  Event pop() {
    const int c = order_.front().cluster;
    std::vector<Event>& mine = filed_[c];
    std::pop_heap(mine.begin(), mine.end(), later);
    const Event e = mine.back();
    mine.pop_back();
    --stored_;
    if (mine.empty()) {
      reposition(c);
    } else {  // c's next event is not earlier: it can only move down
      order_[0].time = mine.front().time;
      sift_down(0);
    }
    return e;
  }

 private:
  struct Entry {
    double time;  // time of the cluster's earliest event (copied for cache-friendly compares)
    std::int32_t cluster;
  };

  bool earlier(const Entry& x, const Entry& y) const {
    if (x.time != y.time) return x.time < y.time;
    return later(filed_[y.cluster].front(), filed_[x.cluster].front());
  }

  // Restores the cluster heap after cluster c's earliest event changed (or vanished).
  void reposition(int c) {
    const bool has_events = !filed_[c].empty();
    std::int32_t k = slot_[c];
    if (k < 0) {
      if (!has_events) return;
      k = static_cast<std::int32_t>(order_.size());
      order_.push_back({0.0, c});
      slot_[c] = k;
    } else if (!has_events) {
      const Entry last = order_.back();
      order_.pop_back();
      slot_[c] = -1;
      if (k == static_cast<std::int32_t>(order_.size())) return;
      order_[k] = last;
      slot_[last.cluster] = k;
      c = last.cluster;
    }
    order_[k].time = filed_[c].front().time;
    sift_up(k);
    sift_down(slot_[c]);
  }

  void place(std::int32_t k, const Entry& e) {
    order_[k] = e;
    slot_[e.cluster] = k;
  }
  static constexpr std::int32_t kArity = 4;
  void sift_up(std::int32_t k) {
    const Entry e = order_[k];
    while (k > 0) {
      const std::int32_t parent = (k - 1) / kArity;
      if (!earlier(e, order_[parent])) break;
      place(k, order_[parent]);
      k = parent;
    }
    place(k, e);
  }
  void sift_down(std::int32_t k) {
    const Entry e = order_[k];
    const auto n = static_cast<std::int32_t>(order_.size());
    while (true) {
      const std::int32_t first = kArity * k + 1;
      if (first >= n) break;
      std::int32_t child = first;
      const std::int32_t last = std::min(first + kArity, n);
      for (std::int32_t c = first + 1; c < last; ++c)
        if (earlier(order_[c], order_[child])) child = c;
      if (!earlier(order_[child], e)) break;
      place(k, order_[child]);
      k = child;
    }
    place(k, e);
  }

  std::vector<std::vector<Event>> filed_;  // per cluster: a binary heap (earliest on top)
  std::vector<std::int32_t> slot_;         // per cluster: index in order_, or -1
  std::vector<Entry> order_;               // 4-ary min-heap of clusters with events
  std::size_t stored_ = 0;
};

}  // namespace ballagg
