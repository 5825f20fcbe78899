#pragma once
// The sphere ids of one cluster, in 8 bytes.
//
// Why: a run starts with one cluster per sphere, and the cluster records are the largest
// table of the state at that moment. A std::vector costs 24 bytes in the record plus a
// heap allocation of at least 32 bytes for every monomer; this list costs 8 bytes and no
// allocation for a single member, which keeps a 2D cluster record within one 64-byte
// cache line (core/state.hpp).
//
// Layout: one 8-byte word. All zero: no member. Low half odd: exactly one member, held in
// the high half. Otherwise the word is a pointer to a heap block {size, capacity, ids...}
// (allocations are 8-aligned, so a pointer's low half is even). A block grows by doubling.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>

namespace ballagg {

class MemberList {
 public:
  using value_type = std::int32_t;

  MemberList() = default;
  MemberList(const MemberList& o) { append(o.begin(), o.end()); }
  MemberList(MemberList&& o) noexcept { take(o); }
  MemberList& operator=(const MemberList& o) {
    if (this != &o) assign(o.begin(), o.end());
    return *this;
  }
  MemberList& operator=(MemberList&& o) noexcept {
    if (this != &o) {
      clear();
      take(o);
    }
    return *this;
  }
  ~MemberList() { clear(); }

  std::size_t size() const {
    if (single()) return 1;
    const std::int32_t* b = block();
    return b == nullptr ? 0 : static_cast<std::size_t>(b[kSize]);
  }
  bool empty() const { return word_[0] == 0 && word_[1] == 0; }

  std::int32_t* data() { return single() ? &word_[1] : ids(block()); }
  const std::int32_t* data() const { return single() ? &word_[1] : ids(block()); }
  std::int32_t* begin() { return data(); }
  std::int32_t* end() { return data() + size(); }
  const std::int32_t* begin() const { return data(); }
  const std::int32_t* end() const { return data() + size(); }
  std::int32_t& operator[](std::size_t k) { return data()[k]; }
  const std::int32_t& operator[](std::size_t k) const { return data()[k]; }
  const std::int32_t& front() const { return data()[0]; }
  operator std::span<const std::int32_t>() const { return {data(), size()}; }

  void push_back(std::int32_t id) { append(&id, &id + 1); }
  // Appends [first, last), which must not lie in this list.
  void append(const std::int32_t* first, const std::int32_t* last) {
    const std::int64_t n = last - first;
    if (n == 0) return;
    const auto old = static_cast<std::int64_t>(size());
    if (old == 0 && n == 1) {
      word_[0] = kSingleTag;
      word_[1] = *first;
      return;
    }
    reserve(old + n);
    std::int32_t* b = block();
    std::copy(first, last, ids(b) + old);
    b[kSize] = static_cast<std::int32_t>(old + n);
  }
  void assign(const std::int32_t* first, const std::int32_t* last) {
    clear();
    append(first, last);
  }
  // Removes the member at pos, keeping the order of the others.
  void erase(const std::int32_t* pos) {
    std::int32_t* d = data();
    const std::int64_t at = pos - d, n = static_cast<std::int64_t>(size());
    if (n == 1) {
      clear();
      return;
    }
    std::copy(d + at + 1, d + n, d + at);
    --block()[kSize];
  }
  // Releases the heap block, if any.
  void clear() {
    if (!single()) delete[] block();
    word_[0] = word_[1] = 0;
  }

 private:
  static constexpr std::int32_t kSingleTag = 1;
  static constexpr int kSize = 0, kCapacity = 1, kHeader = 2;  // a block's leading words

  bool single() const { return (word_[0] & kSingleTag) != 0; }
  std::int32_t* block() const {
    std::int32_t* b;
    std::memcpy(&b, word_, sizeof b);
    return b;
  }
  static std::int32_t* ids(std::int32_t* b) { return b == nullptr ? nullptr : b + kHeader; }
  void set_block(std::int32_t* b) { std::memcpy(word_, &b, sizeof b); }

  void reserve(std::int64_t n) {
    const std::int32_t* b = single() ? nullptr : block();
    const std::int64_t capacity = b == nullptr ? 0 : b[kCapacity];
    if (n <= capacity) return;
    if (n > std::numeric_limits<std::int32_t>::max() - kHeader) throw std::length_error("cluster of more than 2^31 spheres");
    const std::int64_t grown = std::min<std::int64_t>(std::max<std::int64_t>({n, 2 * capacity, 4}),
                                                      std::numeric_limits<std::int32_t>::max() - kHeader);
    auto* fresh = new std::int32_t[grown + kHeader];
    const auto old = static_cast<std::int32_t>(size());
    std::copy(data(), data() + old, fresh + kHeader);
    fresh[kSize] = old;
    fresh[kCapacity] = static_cast<std::int32_t>(grown);
    clear();
    set_block(fresh);
  }
  void take(MemberList& o) {
    word_[0] = std::exchange(o.word_[0], 0);
    word_[1] = std::exchange(o.word_[1], 0);
  }

  alignas(8) std::int32_t word_[2] = {0, 0};
  static_assert(sizeof(std::int32_t*) == 8, "a block pointer fills the word");
};

}  // namespace ballagg
