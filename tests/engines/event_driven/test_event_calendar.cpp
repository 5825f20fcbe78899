// The event calendar gives its events in the total order `later` defines, whatever was
// filed, refiled, forgotten or put back, with many simultaneous events (ties broken by
// kind, then a, then b); a saved and restored calendar gives the same events in the same
// order. A calendar that keeps only the earliest event of each cluster gives the same
// events in the same order, provided each cluster is filed its events again after each
// of its events is popped (as a core that predicts purely does).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <vector>

#include "ballagg/core/random.hpp"
#include "ballagg/engines/event_driven/event_calendar.hpp"

namespace ballagg {
namespace {

bool same(const Event& x, const Event& y) {
  return x.time == y.time && x.a == y.a && x.b == y.b && x.stamp_a == y.stamp_a && x.stamp_b == y.stamp_b &&
         x.kind == y.kind;
}

// The reference: every cluster's events in a plain list; the earliest is the least by `later`.
struct Reference {
  std::map<int, std::vector<Event>> filed;
  std::size_t size() const {
    std::size_t n = 0;
    for (const auto& [c, v] : filed) n += v.size();
    return n;
  }
  Event pop() {
    auto best_c = filed.end();
    std::size_t best_k = 0;
    for (auto it = filed.begin(); it != filed.end(); ++it)
      for (std::size_t k = 0; k < it->second.size(); ++k)
        if (best_c == filed.end() || later(best_c->second[best_k], it->second[k])) best_c = it, best_k = k;
    const Event e = best_c->second[best_k];
    best_c->second.erase(best_c->second.begin() + static_cast<std::ptrdiff_t>(best_k));
    return e;
  }
};

// Drives a calendar and the reference with the same random operations. A calendar that
// keeps the earliest event only is filed again, after each pop from a cluster, with all
// the events the reference still holds for that cluster (a pure prediction gives back
// exactly those).
class CalendarDriver {
 public:
  explicit CalendarDriver(int n_clusters, CalendarKeeps keeps = CalendarKeeps::every_event)
      : rng_(5, RandomPurpose::positions), n_(n_clusters), keeps_(keeps) {
    calendar_.reset(n_clusters, keeps);
  }

  std::vector<Event> batch(int c) {
    std::vector<Event> v(static_cast<std::size_t>(rng_.uniform(0.0, 6.0)));
    for (Event& e : v) {
      // Coarse times and few ids: equal times, kinds and `a` are common; b is unique.
      const auto kind = static_cast<EventKind>(static_cast<int>(rng_.uniform(0.0, 3.0)));
      e = {now_ + 0.25 * std::floor(rng_.uniform(0.0, 8.0)), static_cast<std::int32_t>(rng_.uniform(0.0, 4.0)),
           ++serial_, static_cast<std::uint64_t>(c), serial_ * 3ull, kind};
    }
    return v;
  }

  void step() {
    const int c = static_cast<int>(rng_.uniform(0.0, n_));
    const double what = rng_.uniform();
    if (what < 0.3) {
      const auto v = batch(c);
      calendar_.refile(c, v);
      ref_.filed[c] = v;
    } else if (what < 0.45) {
      const auto v = batch(c);
      calendar_.file(c, v);
      ref_.filed[c].insert(ref_.filed[c].end(), v.begin(), v.end());
    } else if (what < 0.5) {
      calendar_.forget(c);
      ref_.filed.erase(c);
    } else if (!calendar_.empty()) {
      pop_and_check(what < 0.55);
    }
    if (keeps_ == CalendarKeeps::every_event) {
      ASSERT_EQ(calendar_.size(), ref_.size());
    } else {
      ASSERT_LE(calendar_.size(), ref_.size());
      ASSERT_LE(calendar_.size(), static_cast<std::size_t>(n_));
    }
  }

  void pop_and_check(bool put_back) {
    const double earliest = calendar_.earliest_time();
    const Event e = calendar_.pop();
    const int c = static_cast<int>(e.stamp_a);  // stamp_a names the cluster here
    ASSERT_EQ(calendar_.last_popped_from(), c);
    const Event expected = ref_.pop();
    ASSERT_TRUE(same(e, expected)) << e.time << " " << e.a << " " << e.b << " vs " << expected.time << " "
                                   << expected.a << " " << expected.b;
    EXPECT_EQ(earliest, e.time);
    now_ = e.time;
    if (put_back) {
      calendar_.put_back(e);
      ref_.filed[c].push_back(e);
    } else if (keeps_ == CalendarKeeps::earliest_only) {
      calendar_.refile(c, ref_.filed[c]);
      ++refills_;
    }
  }

  EventCalendar calendar_;
  Reference ref_;
  int refills_ = 0;

 private:
  Random rng_;
  int n_;
  CalendarKeeps keeps_;
  double now_ = 0.0;
  std::int32_t serial_ = 0;
};

TEST(EventCalendar, GivesEventsInTheTotalOrder) {
  CalendarDriver d(40);
  for (int step = 0; step < 20000; ++step) ASSERT_NO_FATAL_FAILURE(d.step());
  while (!d.calendar_.empty()) ASSERT_NO_FATAL_FAILURE(d.pop_and_check(false));
  EXPECT_EQ(d.ref_.size(), 0u);
  EXPECT_EQ(d.calendar_.earliest_time(), std::numeric_limits<double>::infinity());
}

// Keeping each cluster's earliest event only, the calendar gives the same events in the
// same order as the reference that keeps all.
TEST(EventCalendar, KeepingTheEarliestEventOnlyGivesTheSameEventsInTheSameOrder) {
  CalendarDriver d(40, CalendarKeeps::earliest_only);
  for (int step = 0; step < 20000; ++step) ASSERT_NO_FATAL_FAILURE(d.step());
  while (d.ref_.size() > 0) ASSERT_NO_FATAL_FAILURE(d.pop_and_check(false));
  EXPECT_GT(d.refills_, 1000);
  EXPECT_TRUE(d.calendar_.empty());
}

// Filing more under a cluster keeps the earliest of what it holds and what comes; a
// refile replaces it, and forgetting drops it.
TEST(EventCalendar, KeepingTheEarliestEventOnlyHoldsOnePerCluster) {
  EventCalendar calendar;
  calendar.reset(2, CalendarKeeps::earliest_only);
  calendar.refile(0, {{3.0, 0, 0, 7, 0, EventKind::wall}, {1.0, 0, 0, 7, 0, EventKind::list_rebuild},
                      {1.0, 0, 5, 7, 9, EventKind::collision}});
  calendar.file(1, {{2.0, 1, 0, 4, 0, EventKind::collision}});
  calendar.file(1, {{2.5, 1, 1, 4, 0, EventKind::collision}});
  EXPECT_EQ(calendar.size(), 2u);
  Event e = calendar.pop();  // at t = 1 the collision comes before the rebuild
  EXPECT_EQ(e.kind, EventKind::collision);
  EXPECT_EQ(e.b, 5);
  EXPECT_EQ(calendar.last_popped_from(), 0);
  EXPECT_EQ(calendar.size(), 1u);
  calendar.put_back(e);
  EXPECT_EQ(calendar.pop().b, 5);
  calendar.file(0, {{2.25, 0, 0, 7, 0, EventKind::list_rebuild}});
  calendar.file(1, {{1.5, 1, 2, 4, 0, EventKind::collision}});
  e = calendar.pop();
  EXPECT_EQ(e.time, 1.5);
  EXPECT_EQ(calendar.last_popped_from(), 1);
  calendar.refile(0, {{4.0, 0, 0, 8, 0, EventKind::wall}});
  e = calendar.pop();
  EXPECT_EQ(e.time, 4.0);
  EXPECT_TRUE(calendar.empty());
  calendar.file(1, {{5.0, 1, 0, 4, 0, EventKind::wall}});
  calendar.forget(1);
  EXPECT_TRUE(calendar.empty());
  EXPECT_EQ(calendar.size(), 0u);
}

// With every event kept and with the earliest only.
TEST(EventCalendar, SavedAndRestoredGivesTheSameEvents) {
  for (CalendarKeeps keeps : {CalendarKeeps::every_event, CalendarKeeps::earliest_only}) {
    SCOPED_TRACE(static_cast<int>(keeps));
    CalendarDriver d(30, keeps);
    for (int step = 0; step < 3000; ++step) ASSERT_NO_FATAL_FAILURE(d.step());
    ByteWriter w;
    d.calendar_.save(w);
    EventCalendar copy;
    copy.reset(30, keeps);
    ByteReader r(w.bytes(), "calendar");
    copy.restore(r, [&](const Event&) {});
    ByteWriter again;
    copy.save(again);
    EXPECT_EQ(again.bytes(), w.bytes());
    ASSERT_EQ(copy.size(), d.calendar_.size());
    while (!copy.empty()) {
      const Event e = copy.pop();
      ASSERT_TRUE(same(e, d.calendar_.pop()));
    }
    EXPECT_TRUE(d.calendar_.empty());
  }
}

// A calendar saved with every event kept, restored into one that keeps the earliest only,
// keeps each cluster's earliest. A refill marker in the file (a copy of an event, its
// second stamp 2^63 + its cluster) is read as its copied event with stamps 0, which no
// cluster has: found stale when due.
TEST(EventCalendar, RestoringKeepsTheEarliestAndReadsRefillMarkers) {
  EventCalendar all;
  all.reset(2);
  all.refile(0, {{3.0, 0, 0, 7, 0, EventKind::wall}, {1.0, 0, 0, 7, 0, EventKind::list_rebuild}});
  all.refile(1, {{2.0, 1, 0, 4, 0, EventKind::wall}});
  ByteWriter w;
  all.save(w);
  // A third cluster, saved with a marker standing for its events.
  w.put<std::uint32_t>(1);
  w.put(0.5);
  w.put<std::int32_t>(2);
  w.put<std::int32_t>(0);
  w.put<std::uint64_t>(9);
  w.put<std::uint64_t>((std::uint64_t{1} << 63) | 2);
  w.put(EventKind::list_rebuild);
  EventCalendar earliest;
  earliest.reset(3, CalendarKeeps::earliest_only);
  ByteReader r(w.bytes(), "calendar");
  earliest.restore(r, [](const Event&) {});
  EXPECT_EQ(earliest.size(), 3u);
  Event e = earliest.pop();
  EXPECT_EQ(e.time, 0.5);
  EXPECT_EQ(e.a, 2);
  EXPECT_EQ(e.stamp_a, 0u);
  EXPECT_EQ(e.stamp_b, 0u);
  EXPECT_EQ(earliest.pop().time, 1.0);
  EXPECT_EQ(earliest.pop().time, 2.0);
  EXPECT_TRUE(earliest.empty());
}

TEST(EventCalendar, ForgottenClustersGiveNoEvents) {
  EventCalendar calendar;
  calendar.reset(3);
  calendar.refile(0, {{1.0, 0, 0, 1, 0, EventKind::wall}, {2.0, 0, 1, 1, 0, EventKind::wall}});
  calendar.refile(2, {{0.5, 2, 0, 1, 0, EventKind::list_rebuild}});
  calendar.forget(2);
  calendar.forget(1);  // nothing filed: nothing changes
  EXPECT_EQ(calendar.size(), 2u);
  EXPECT_EQ(calendar.pop().time, 1.0);
  calendar.refile(0, {});
  EXPECT_TRUE(calendar.empty());
  EXPECT_EQ(calendar.size(), 0u);
}

// The stored 32-byte form gives back the event it was made from, and orders events exactly
// as `later` does, kinds, ids and the largest stamps included.
TEST(EventCalendar, FiledEventsKeepTheEventAndItsOrder) {
  Random rng(9, RandomPurpose::positions);
  const std::uint64_t largest = FiledEvent::kStampLimit - 1;
  std::vector<Event> events;
  for (int k = 0; k < 300; ++k) {
    const auto kind = static_cast<EventKind>(static_cast<int>(rng.uniform(0.0, 5.0)));
    const auto stamp = k % 7 == 0 ? largest : static_cast<std::uint64_t>(rng.uniform(0.0, 1e18));
    events.push_back({std::floor(rng.uniform(0.0, 3.0)), static_cast<std::int32_t>(rng.uniform(0.0, 3.0)),
                      static_cast<std::int32_t>(rng.uniform(-8.0, 3.0)), stamp, largest - k, kind});
  }
  for (const Event& x : events) {
    EXPECT_TRUE(same(FiledEvent(x).event(), x));
    for (const Event& y : events) ASSERT_EQ(filed_later(FiledEvent(x), FiledEvent(y)), later(x, y));
  }
}

TEST(EventCalendar, RefusesAStampBeyondItsBits) {
  EventCalendar calendar;
  calendar.reset(1);
  const Event beyond{1.0, 0, 1, FiledEvent::kStampLimit, 0, EventKind::collision};
  EXPECT_THROW(calendar.file(0, {beyond}), std::length_error);
  EXPECT_THROW(calendar.refile(0, {beyond}), std::length_error);

  ByteWriter w;  // a saved calendar of one cluster holding that event
  w.put<std::uint32_t>(1);
  w.put(beyond.time);
  w.put(beyond.a);
  w.put(beyond.b);
  w.put(beyond.stamp_a);
  w.put(beyond.stamp_b);
  w.put(beyond.kind);
  ByteReader r(w.bytes(), "calendar");
  EXPECT_THROW(calendar.restore(r, [](const Event&) {}), CheckpointError);
}

}  // namespace
}  // namespace ballagg
