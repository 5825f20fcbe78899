#pragma once
// One short list of trivially copyable values per owner (a cluster, a sphere), all kept in
// one pool of blocks instead of a fixed in-place array per owner.
//
// Why: most owners hold one or two values, a few hold hundreds, and after merges most
// owners are dead and hold none. An in-place array sized for the common case costs its
// full size for every owner, dead ones included, and spills to a heap allocation beyond
// it. Here an owner costs an 8-byte handle; its values live in one block of the pool.
//
// Layout: a block holds 2^k values (a size class); an owner's block grows by doubling,
// and a freed block goes on the free list of its class, where the next block of that class
// is taken from. Free lists are threaded through the free blocks themselves, so they cost
// no memory. Blocks are carved from chunks of 2^kChunkLog values that never move: a
// pointer to an owner's values stays valid until that owner's list grows, shrinks or is
// released, whatever the other owners do; and growing the pool never copies it (a vector
// that doubled would hold the old and the new copy at once, twice the memory at its
// peak). A block larger than a chunk gets an allocation of its own, spanning as many chunk
// numbers. Chunk memory is allocated without being written, so pages that no block has
// used yet cost no resident memory.
//
// An element index (chunk number and place in it) is 32 bits: the pool holds at most 2^32
// values, an owner at most kMaxSize = 2^26; beyond either it throws std::length_error.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace ballagg {

template <class T, int kChunkLog = 14>
class PooledLists {
  static_assert(std::is_trivially_copyable_v<T> && sizeof(T) >= sizeof(std::uint32_t),
                "a free block stores the next free block's index in its first value");
  static_assert(kChunkLog >= 0 && kChunkLog < 32);

 public:
  static constexpr std::uint32_t kMaxSize = std::uint32_t{1} << 26;  // values per owner

  PooledLists() { free_.fill(kNoBlock); }
  PooledLists(const PooledLists&) = delete;  // data() pointers point into this pool
  PooledLists& operator=(const PooledLists&) = delete;

  // n_owners empty lists; the pool's memory is released.
  void reset(int n_owners) {
    slot_.assign(static_cast<std::size_t>(n_owners), Slot{});
    chunks_.clear();
    chunks_.shrink_to_fit();
    free_.fill(kNoBlock);
    bump_ = end_ = 0;
  }

  int owners() const { return static_cast<int>(slot_.size()); }
  std::uint32_t size(int o) const { return slot_[o].count; }
  bool empty(int o) const { return slot_[o].count == 0; }
  std::uint32_t capacity(int o) const { return capacity_of(slot_[o].cls); }
  T* data(int o) { return block(slot_[o]); }
  const T* data(int o) const { return block(slot_[o]); }
  T& front(int o) { return *data(o); }
  const T& front(int o) const { return *data(o); }
  T* begin(int o) { return data(o); }
  T* end(int o) { return data(o) + slot_[o].count; }
  const T* begin(int o) const { return data(o); }
  const T* end(int o) const { return data(o) + slot_[o].count; }

  void push_back(int o, const T& x) {
    Slot& s = slot_[o];
    if (s.count == capacity_of(s.cls)) move_to_class(s, s.cls + 1);
    block(s)[s.count++] = x;
  }
  void pop_back(int o) { --slot_[o].count; }  // requires !empty(o); keeps the block
  void clear(int o) { slot_[o].count = 0; }   // keeps the block

  // Replaces owner o's values by [first, first + n). The block is kept if it fits n and is
  // at most kSlack times the smallest block that does, so that a list whose length wavers
  // does not move at every change; otherwise the values move to a block of the least class.
  // The values are converted to T one by one (T(first[i])).
  template <class It>
  void assign(int o, It first, std::size_t n) {
    Slot& s = slot_[o];
    const std::uint32_t least = class_for(n);
    s.count = 0;
    if (capacity_of(s.cls) < n || s.cls > least + kSlackClasses) move_to_class(s, least);
    T* values = block(s);
    for (std::size_t i = 0; i < n; ++i) values[i] = T(first[i]);
    s.count = static_cast<std::uint32_t>(n);
  }

  // Drops owner o's values and returns its block to the pool.
  void release(int o) {
    Slot& s = slot_[o];
    if (s.cls != 0) free_block(s.offset, s.cls);
    s = Slot{};
  }
  // Appends owner from's values, in order, to owner to's list (from != to), in one copy,
  // and releases from's block.
  void append_owner(int to, int from) {
    Slot& t = slot_[to];
    const Slot f = slot_[from];
    const std::size_t n = std::size_t{t.count} + f.count;
    if (n > capacity_of(t.cls)) move_to_class(t, class_for(n));
    if (f.count != 0) std::memcpy(static_cast<void*>(block(t) + t.count), block(f), f.count * sizeof(T));
    t.count = static_cast<std::uint32_t>(n);
    release(from);
  }
  // Owners a and b exchange their lists; no value moves.
  void swap_owners(int a, int b) { std::swap(slot_[a], slot_[b]); }

  // Releases the last owner and removes it: owners stay dense when one leaves for good.
  void pop_owner() {
    release(owners() - 1);
    slot_.pop_back();
  }

 private:
  static constexpr std::uint32_t kNoBlock = ~std::uint32_t{0};
  static constexpr std::uint32_t kChunk = std::uint32_t{1} << kChunkLog;
  static constexpr std::uint32_t kSlackClasses = 2;  // a block up to 4x the least is kept
  static constexpr std::uint32_t kClasses = 28;      // cls 0 (no block) .. 27 (2^26 values)

  // cls 0: no block; cls k > 0: a block of 2^(k-1) values starting at element `offset`.
  // count <= kMaxSize < 2^27.
  struct Slot {
    std::uint32_t offset = 0;
    std::uint32_t count : 27 = 0;
    std::uint32_t cls : 5 = 0;
  };
  static_assert(sizeof(Slot) == 8);

  static std::uint32_t capacity_of(std::uint32_t cls) { return cls == 0 ? 0 : std::uint32_t{1} << (cls - 1); }
  static std::uint32_t class_for(std::size_t n) {
    if (n > kMaxSize) throw std::length_error("pooled lists: more than 2^26 values in one list");
    return static_cast<std::uint32_t>(std::bit_width(std::bit_ceil(std::max<std::size_t>(n, 1))));
  }

  T* at(std::uint32_t offset) const { return chunks_[offset >> kChunkLog].get() + (offset & (kChunk - 1)); }
  T* block(const Slot& s) const { return s.cls == 0 ? nullptr : at(s.offset); }

  // Moves owner s's values into a new block of class cls and frees the old block.
  void move_to_class(Slot& s, std::uint32_t cls) {
    if (cls >= kClasses) throw std::length_error("pooled lists: more than 2^26 values in one list");
    const std::uint32_t offset = allocate(cls);
    if (s.count != 0) std::memcpy(static_cast<void*>(at(offset)), at(s.offset), s.count * sizeof(T));
    if (s.cls != 0) free_block(s.offset, s.cls);
    s.offset = offset;
    s.cls = cls;
  }

  std::uint32_t allocate(std::uint32_t cls) {
    if (const std::uint32_t head = free_[cls]; head != kNoBlock) {
      std::memcpy(&free_[cls], at(head), sizeof(std::uint32_t));
      return head;
    }
    const std::uint32_t n = capacity_of(cls);
    if (n > kChunk) return allocate_chunks(n / kChunk, n);
    if (end_ - bump_ < n) open_chunk();
    const std::uint32_t offset = bump_;
    bump_ += n;
    return offset;
  }
  void free_block(std::uint32_t offset, std::uint32_t cls) {
    std::memcpy(static_cast<void*>(at(offset)), &free_[cls], sizeof(std::uint32_t));
    free_[cls] = offset;
  }

  // Files the rest of the current chunk as free blocks (powers of two, the largest first)
  // and starts a fresh chunk.
  void open_chunk() {
    for (std::uint32_t rest = end_ - bump_; rest != 0; rest = end_ - bump_) {
      const std::uint32_t piece = std::bit_floor(rest);
      free_block(bump_, static_cast<std::uint32_t>(std::bit_width(piece)));
      bump_ += piece;
    }
    bump_ = allocate_chunks(1, kChunk);
    end_ = bump_ + kChunk;
  }
  // n_chunks consecutive chunk numbers backed by one allocation of n values.
  std::uint32_t allocate_chunks(std::size_t n_chunks, std::size_t n) {
    if (chunks_.size() + n_chunks > (std::size_t{1} << (32 - kChunkLog)))
      throw std::length_error("pooled lists: more than 2^32 values in the pool");
    const auto offset = static_cast<std::uint32_t>(chunks_.size() << kChunkLog);
    chunks_.push_back(std::make_unique_for_overwrite<T[]>(n));
    chunks_.resize(chunks_.size() + n_chunks - 1);  // spanned by the allocation above
    return offset;
  }

  std::vector<Slot> slot_;                  // per owner
  std::vector<std::unique_ptr<T[]>> chunks_;
  std::array<std::uint32_t, kClasses> free_{};  // per class: the first free block, or kNoBlock
  std::uint32_t bump_ = 0, end_ = 0;        // the unused rest of the current chunk
};

}  // namespace ballagg
