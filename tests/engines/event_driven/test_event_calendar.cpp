// The event calendar gives its events in the total order `later` defines, whatever was
// filed, refiled, forgotten or put back, with many simultaneous events (ties broken by
// kind, then a, then b); a saved and restored calendar gives the same events in the same
// order. A calendar that keeps only the earliest events of each cluster gives the same
// events in the same order, provided each due refill marker is answered with the cluster's
// events again (as a core that predicts purely does).
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

// Drives a calendar and the reference with the same random operations. With `kept` > 0 the
// calendar keeps that many events per cluster; a refill marker it gives is answered by
// refiling the cluster with all its events the reference still holds (a pure prediction
// gives back exactly those), and never reaches the comparison.
class CalendarDriver {
 public:
  explicit CalendarDriver(int n_clusters, int kept = 0) : rng_(5, RandomPurpose::positions), n_(n_clusters), kept_(kept) {
    calendar_.reset(n_clusters);
    calendar_.keep_at_most(kept);
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
      calendar_.refile(c, v, static_cast<std::uint64_t>(c));
      ref_.filed[c] = v;
    } else if (what < 0.45) {
      const auto v = batch(c);
      calendar_.file(c, v, static_cast<std::uint64_t>(c));
      ref_.filed[c].insert(ref_.filed[c].end(), v.begin(), v.end());
    } else if (what < 0.5) {
      calendar_.forget(c);
      ref_.filed.erase(c);
    } else if (!calendar_.empty()) {
      pop_and_check(what < 0.55);
    }
    if (kept_ == 0) {
      ASSERT_EQ(calendar_.size(), ref_.size());
    } else {
      ASSERT_LE(calendar_.size(), ref_.size());
      ASSERT_LE(calendar_.size(), static_cast<std::size_t>((kept_ + 1) * n_));
    }
  }

  void pop_and_check(bool put_back) {
    const double earliest = calendar_.earliest_time();
    Event e = calendar_.pop();
    bool refilled = false;
    int refills_here = 0;
    while (e.kind == EventKind::refill) {
      ASSERT_LT(++refills_here, 100) << "refills go round";
      const int c = e.a;
      ASSERT_EQ(e.stamp_a, static_cast<std::uint64_t>(c));
      const std::vector<Event>& left = ref_.filed[c];
      ASSERT_FALSE(left.empty()) << "a marker stands for no event";
      for (const Event& x : left) ASSERT_LE(e.time, x.time) << "a marker later than an event it stands for";
      calendar_.refile(c, left, static_cast<std::uint64_t>(c));
      ++refills_;
      refilled = true;
      ASSERT_FALSE(calendar_.empty());
      e = calendar_.pop();
    }
    const Event expected = ref_.pop();
    ASSERT_TRUE(same(e, expected)) << e.time << " " << e.a << " " << e.b << " vs " << expected.time << " "
                                   << expected.a << " " << expected.b;
    if (!refilled) {
      EXPECT_EQ(earliest, e.time);
    }
    now_ = e.time;
    if (put_back) {
      calendar_.put_back(e);
      ref_.filed[static_cast<int>(e.stamp_a)].push_back(e);  // stamp_a names the cluster here
    }
  }

  EventCalendar calendar_;
  Reference ref_;
  int refills_ = 0;

 private:
  Random rng_;
  int n_;
  int kept_;
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

// Kept to one, two or three events per cluster, the calendar gives the same events in the
// same order as the reference that keeps all, with markers answered along the way.
TEST(EventCalendar, KeepingTheEarliestEventsGivesTheSameEventsInTheSameOrder) {
  for (int kept : {1, 2, 3}) {
    SCOPED_TRACE(kept);
    CalendarDriver d(40, kept);
    for (int step = 0; step < 20000; ++step) ASSERT_NO_FATAL_FAILURE(d.step());
    while (d.ref_.size() > 0) ASSERT_NO_FATAL_FAILURE(d.pop_and_check(false));
    EXPECT_GT(d.refills_, 100);  // the bound was reached, and markers came due
    EXPECT_TRUE(d.calendar_.empty());
  }
}

// A marker stands for the earliest event left out, and comes first among events at its time.
TEST(EventCalendar, ARefillMarkerStandsForTheEarliestEventLeftOut) {
  EventCalendar calendar;
  calendar.reset(2);
  calendar.keep_at_most(1);
  calendar.refile(0, {{3.0, 0, 0, 7, 0, EventKind::wall}, {1.0, 0, 0, 7, 0, EventKind::list_rebuild},
                      {2.0, 0, 5, 7, 9, EventKind::collision}}, 7);
  calendar.refile(1, {{2.0, 1, 0, 4, 0, EventKind::collision}});
  EXPECT_EQ(calendar.size(), 3u);  // one event and a marker under cluster 0
  Event e = calendar.pop();
  EXPECT_EQ(e.time, 1.0);
  EXPECT_EQ(e.kind, EventKind::list_rebuild);
  e = calendar.pop();  // at t = 2 the marker goes before the collision of cluster 1
  EXPECT_EQ(e.kind, EventKind::refill);
  EXPECT_EQ(e.time, 2.0);
  EXPECT_EQ(e.a, 0);
  EXPECT_EQ(e.stamp_a, 7u);
  // Filing more under a cluster with a marker keeps the marker at the sooner time.
  calendar.refile(0, {{3.0, 0, 0, 7, 0, EventKind::wall}, {2.5, 0, 6, 7, 9, EventKind::collision}}, 7);
  calendar.file(0, {{2.25, 0, 0, 7, 0, EventKind::list_rebuild}}, 7);
  e = calendar.pop();
  EXPECT_EQ(e.kind, EventKind::collision);  // cluster 1's, at 2.0
  e = calendar.pop();
  EXPECT_EQ(e.time, 2.25);
  EXPECT_EQ(e.kind, EventKind::list_rebuild);
  e = calendar.pop();
  EXPECT_EQ(e.kind, EventKind::refill);
  EXPECT_EQ(e.time, 2.5);
  EXPECT_TRUE(calendar.empty());
}

// With every event kept and with one kept (its markers saved as they are).
TEST(EventCalendar, SavedAndRestoredGivesTheSameEvents) {
  for (int kept : {0, 1}) {
    SCOPED_TRACE(kept);
    CalendarDriver d(30, kept);
    for (int step = 0; step < 3000; ++step) ASSERT_NO_FATAL_FAILURE(d.step());
    ByteWriter w;
    d.calendar_.save(w);
    EventCalendar copy;
    copy.reset(30);
    copy.keep_at_most(kept);
    ByteReader r(w.bytes(), "calendar");
    int markers = 0;
    copy.restore(r, [&](const Event& e) { markers += e.kind == EventKind::refill; });
    EXPECT_EQ(markers > 0, kept > 0);
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
