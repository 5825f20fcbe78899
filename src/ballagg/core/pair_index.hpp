#pragma once
// A hash map from unordered pairs of ids (i, j) to an int32 value, with open addressing
// and linear probing in one flat array. The time-stepping engine asks "is (i, j) in the
// adhesive set S already?" for every contact it finds, and S holds up to a million pairs in
// the first steps of a large run: std::unordered_map spent most of its time allocating a
// node per pair. Clearing costs the number of entries, not the capacity. A table left far
// larger than what it held is shrunk at clear() to a small front part of its storage, so
// that the lookups of the many small sets that follow a large one stay in cache (a table
// of a million pairs left behind would make every later lookup a cache miss). The storage
// itself is kept, at the cost of the largest table's memory for the rest of the run: the
// early steps of a large run alternate large and small sets, and a table allocated afresh
// for each large one would be zeroed and faulted in page by page every time, on the main
// thread alone.
#include <cstdint>
#include <utility>
#include <vector>

#include "ballagg/core/prefetch.hpp"

namespace ballagg {

class PairIndex {
 public:
  static constexpr std::int32_t kAbsent = -1;

  // The value stored for (i, j), or kAbsent.
  std::int32_t find(std::int32_t i, std::int32_t j) const {
    if (capacity_ == 0) return kAbsent;
    const std::uint64_t key = pack(i, j);
    for (std::size_t s = home(key);; s = (s + 1) & mask_) {
      if (slots_[s].key == kEmpty) return kAbsent;
      if (slots_[s].key == key) return slots_[s].value;
    }
  }

  // Asks for the slot where a search for (i, j) starts (a hint: it changes nothing). A
  // large table is far larger than the caches, and each search waits for that slot.
  void prefetch(std::int32_t i, std::int32_t j) const {
    if (capacity_ != 0) ballagg::prefetch(&slots_[home(pack(i, j))]);
  }

  // Stores value for (i, j) unless the pair is there; returns {stored value, inserted}.
  std::pair<std::int32_t, bool> insert(std::int32_t i, std::int32_t j, std::int32_t value) {
    if (2 * (used_.size() + 1) > capacity_) grow();
    const std::uint64_t key = pack(i, j);
    for (std::size_t s = home(key);; s = (s + 1) & mask_) {
      if (slots_[s].key == key) return {slots_[s].value, false};
      if (slots_[s].key == kEmpty) {
        slots_[s] = {key, value};
        used_.push_back(static_cast<std::uint32_t>(s));
        return {value, true};
      }
    }
  }

  // Room for `n` entries without growing (rehashing at each doubling while a large set is
  // filled would weigh on the serial part of the detection).
  // Grown at once to the size needed: growing by doublings from an emptied table would fill
  // every intermediate table too (twice the memory written, each page faulted in afresh).
  void reserve(std::size_t n) {
    std::size_t capacity = capacity_ == 0 ? kMinCapacity : capacity_;
    while (2 * n > capacity) capacity *= 2;
    if (capacity > capacity_) rehash(capacity);
  }

  std::size_t size() const { return used_.size(); }
  // The slots in use for hashing (the storage may be larger: see clear()).
  std::size_t capacity() const { return capacity_; }

  void clear() {
    for (std::uint32_t s : used_) slots_[s].key = kEmpty;
    // Emptied and mostly unused: hash into a small front part of the storage again (the
    // next insert grows it as needed, within the storage kept).
    if (capacity_ > kMinCapacity && capacity_ > kShrinkRatio * 2 * used_.size()) set_capacity(kMinCapacity);
    used_.clear();
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  // The capacity a table starts with, and the factor by which a table may outsize twice
  // its entries at clear() before it is given back.
  static constexpr std::size_t kMinCapacity = 1024;
  static constexpr std::size_t kShrinkRatio = 16;
  struct Slot {
    std::uint64_t key = kEmpty;
    std::int32_t value = kAbsent;
  };

  static std::uint64_t pack(std::int32_t i, std::int32_t j) {
    if (i > j) std::swap(i, j);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
  }
  // Fibonacci hashing: the high bits of key * 2^64 / phi, spread over the table.
  std::size_t home(std::uint64_t key) const { return (key * 0x9E3779B97F4A7C15ull) >> shift_; }

  void grow() { rehash(capacity_ == 0 ? kMinCapacity : 2 * capacity_); }

  void set_capacity(std::size_t capacity) {
    capacity_ = capacity;
    mask_ = capacity - 1;
    shift_ = 64;
    for (std::size_t c = capacity; c > 1; c >>= 1) --shift_;
  }

  // Hashes the entries into `capacity` slots (a power of two), in the storage kept when it
  // is large enough (every slot not in use holds kEmpty there), else in a larger one.
  void rehash(std::size_t capacity) {
    std::vector<Slot> entries;
    entries.reserve(used_.size());
    for (std::uint32_t s : used_) {
      entries.push_back(slots_[s]);
      slots_[s].key = kEmpty;
    }
    used_.clear();
    if (capacity > slots_.size()) {
      std::vector<Slot>().swap(slots_);  // given back before the larger one is taken
      slots_.assign(capacity, Slot{});
    }
    set_capacity(capacity);
    for (const Slot& e : entries) {
      std::size_t t = home(e.key);
      while (slots_[t].key != kEmpty) t = (t + 1) & mask_;
      slots_[t] = e;
      used_.push_back(static_cast<std::uint32_t>(t));
    }
  }

  std::vector<Slot> slots_;          // the storage: its first capacity_ slots are the table
  std::vector<std::uint32_t> used_;  // occupied slots, for clear()
  std::size_t capacity_ = 0;
  std::size_t mask_ = 0;
  int shift_ = 64;
};

}  // namespace ballagg
