#pragma once
// An indexed priority queue of keys (cluster ids) by time, as a calendar queue of buckets
// (Brown 1988; Marin et al. 1993 and Paul 2007 for event-driven molecular dynamics).
//
// Why not a heap of all keys: the event calendar repositions a cluster after every event
// (its earliest event changed), and a heap pays O(log M) comparisons on scattered memory
// for each. Here a key lives in the bucket that holds its time; moving it between buckets
// is an unlink and a link, O(1). Only the current (earliest non-empty) bucket is kept as a
// small binary heap, so that a pile of equal times (a lattice start with equal speeds
// puts thousands of rebuilds at one instant) still costs O(log) per pop.
//
// Exactness: the bucket of time t is floor((t - origin) / width), monotone in t, so every
// key of an earlier bucket is strictly earlier and equal times share a bucket; the top of
// the current bucket's heap under the caller's total order is the top of the queue. Bucket
// widths affect only the speed, never which key comes first.
//
// Buckets cover one "year" [origin, origin + n width); later keys wait in an overflow
// list. When the current bucket passes the end of the year the queue is rebuilt from the
// keys it holds: origin at the earliest time, the width such that the earlier half of the
// keys falls about kKeysPerBucket to a bucket, n about the number of keys. A year lasts
// at least until that earlier half has come up, so the O(keys) rebuild is paid back over
// as many pops.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace ballagg {

// `Earlier(a, b)` orders keys a and b of equal time (a strict total order).
template <class Earlier>
class BucketQueue {
 public:
  explicit BucketQueue(Earlier earlier) : earlier_(earlier) {}

  void reset(int n_keys) {
    key_.assign(n_keys, Key{});
    head_.clear();
    front_.clear();
    overflow_ = kNone;
    current_ = 0;
    origin_ = 0.0;
    width_ = 1.0;
    size_ = 0;
  }

  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  bool contains(int k) const { return key_[k].next != kAbsent; }

  // Files key k at `time` (moving it if it was filed already). `time` must be finite: a
  // NaN has no bucket and a queue of keys at +infinity has no earliest bucket, so either
  // would make top() search for ever. Engines file only events that happen; an engine
  // that computes another time is broken, and says so here rather than hanging.
  void update(int k, double time) {
    if (!std::isfinite(time)) throw std::logic_error("event calendar: an event at a time that is not finite");
    // Within a list order does not matter: an unchanged time needs no move.
    if (in_list(k) && key_[k].time == time) return;
    if (contains(k)) detach(k); else ++size_;
    key_[k].time = time;
    attach(k);
  }

  void remove(int k) {
    if (!contains(k)) return;
    detach(k);
    key_[k].next = kAbsent;
    --size_;
  }

  // The earliest key. Requires !empty().
  int top() {
    while (front_.empty()) advance();
    return front_.front();
  }

 private:
  static constexpr std::int32_t kNone = -1;
  static constexpr std::int32_t kAbsent = -2;
  static constexpr std::int32_t kOverflow = -3;
  static constexpr std::int32_t kFront = -4;
  static constexpr double kKeysPerBucket = 2.0;
  static constexpr std::size_t kFrontCapacityKept = 1024;  // keys; a larger front heap is freed at a rebuild

  // 16 bytes: where a key is filed is told by `next` (kAbsent, kFront, or a list's next key
  // or kNone), and which list holds it by its time (list_head), as attach() chose it.
  struct Key {
    double time = 0.0;
    std::int32_t next = kAbsent;     // in a list: the next key or kNone; else kFront or kAbsent
    std::int32_t prev = kNone;       // in a list: the previous key or kNone; in the front heap: its index
  };
  static_assert(sizeof(Key) == 16);

  bool before(std::int32_t a, std::int32_t b) const {
    const double ta = key_[a].time, tb = key_[b].time;
    return ta < tb || (ta == tb && earlier_(a, b));
  }

  // Keys due no later than the current bucket (including events predicted at the present
  // instant whose time rounds below it) join the front heap.
  void attach(std::int32_t k) {
    const std::int32_t bucket = bucket_of(key_[k].time);
    if (bucket == kOverflow) return link(k, overflow_);
    if (bucket <= current_) return push_front(k);
    link(k, head_[bucket]);
  }
  void detach(std::int32_t k) {
    if (key_[k].next == kFront) erase_front(k); else unlink(k);
  }
  bool in_list(std::int32_t k) const { return key_[k].next >= kNone; }

  // The bucket of `time` in this year, or kOverflow beyond it: a function of the time and
  // the year only, so a listed key's list is found again from its time.
  std::int32_t bucket_of(double time) const {
    const double rel = (time - origin_) / width_;
    if (!(rel < static_cast<double>(head_.size()))) return kOverflow;
    return static_cast<std::int32_t>(std::max(rel, 0.0));
  }
  std::int32_t& list_head(std::int32_t k) {
    const std::int32_t bucket = bucket_of(key_[k].time);
    return bucket == kOverflow ? overflow_ : head_[bucket];
  }
  void link(std::int32_t k, std::int32_t& head) {
    Key& e = key_[k];
    e.prev = kNone;
    e.next = head;
    if (head != kNone) key_[head].prev = k;
    head = k;
  }
  void unlink(std::int32_t k) {
    const Key& e = key_[k];
    if (e.prev != kNone) key_[e.prev].next = e.next; else list_head(k) = e.next;
    if (e.next != kNone) key_[e.next].prev = e.prev;
  }

  // Moves to the next non-empty bucket and heaps its keys; rebuilds at the end of the year.
  void advance() {
    ++current_;
    if (current_ >= static_cast<std::int32_t>(head_.size())) return rebuild();
    for (std::int32_t k = head_[current_]; k != kNone;) {
      const std::int32_t next = key_[k].next;
      push_front(k);
      k = next;
    }
    head_[current_] = kNone;
  }

  // ---- the front heap (binary, indexed through Key::prev) ----
  void place(std::size_t i, std::int32_t k) {
    front_[i] = k;
    key_[k].prev = static_cast<std::int32_t>(i);
  }
  void push_front(std::int32_t k) {
    key_[k].next = kFront;
    front_.push_back(k);
    sift_up(front_.size() - 1);
  }
  void erase_front(std::int32_t k) {
    const auto i = static_cast<std::size_t>(key_[k].prev);
    const std::int32_t last = front_.back();
    front_.pop_back();
    if (i == front_.size()) return;
    place(i, last);
    sift_up(i);
    sift_down(static_cast<std::size_t>(key_[last].prev));
  }
  void sift_up(std::size_t i) {
    const std::int32_t k = front_[i];
    while (i > 0) {
      const std::size_t parent = (i - 1) / 2;
      if (!before(k, front_[parent])) break;
      place(i, front_[parent]);
      i = parent;
    }
    place(i, k);
  }
  void sift_down(std::size_t i) {
    const std::int32_t k = front_[i];
    const std::size_t n = front_.size();
    while (2 * i + 1 < n) {
      std::size_t child = 2 * i + 1;
      if (child + 1 < n && before(front_[child + 1], front_[child])) ++child;
      if (!before(front_[child], k)) break;
      place(i, front_[child]);
      i = child;
    }
    place(i, k);
  }

  // Starts a new year at the earliest key, with the width fitted to the keys' times. The
  // scratch lists are local and the front heap gives back a large capacity: a pile of
  // simultaneous keys at the start must not keep its memory for the whole run.
  void rebuild() {
    std::vector<std::int32_t> held(front_.begin(), front_.end());
    for (std::int32_t h : head_)
      for (std::int32_t k = h; k != kNone; k = key_[k].next) held.push_back(k);
    for (std::int32_t k = overflow_; k != kNone; k = key_[k].next) held.push_back(k);
    fit_year(held);
    std::size_t n = 16;
    while (n < held.size()) n *= 2;
    head_.assign(n, kNone);
    front_.clear();
    if (front_.capacity() > kFrontCapacityKept) std::vector<std::int32_t>().swap(front_);
    overflow_ = kNone;
    current_ = 0;
    for (std::int32_t k : held) attach(k);
  }
  // origin at the earliest time; width such that the earlier half of the keys falls about
  // kKeysPerBucket to a bucket.
  void fit_year(const std::vector<std::int32_t>& held) {
    std::vector<double> times;
    times.reserve(held.size());
    for (std::int32_t k : held) times.push_back(key_[k].time);
    const auto half = times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2);
    std::nth_element(times.begin(), half, times.end());
    origin_ = *std::min_element(times.begin(), half + 1);
    const double half_count = std::max(1.0, static_cast<double>(times.size() / 2));
    width_ = kKeysPerBucket * (*half - origin_) / half_count;
    if (!(width_ > 0.0) || !std::isfinite(width_)) width_ = 1.0;
  }

  Earlier earlier_;
  std::vector<Key> key_;             // per key
  std::vector<std::int32_t> head_;   // per bucket of the year: first key, or kNone
  std::vector<std::int32_t> front_;  // the current bucket, as a binary heap
  std::int32_t overflow_ = kNone;    // keys beyond the year
  std::int32_t current_ = 0;         // buckets before it are empty; its keys are in front_
  double origin_ = 0.0, width_ = 1.0;
  std::size_t size_ = 0;
};

}  // namespace ballagg
