#pragma once
// A vector of trivially copyable values that stores up to N of them in place and spills
// to the heap beyond. The event-driven engine keeps one per cluster (its exposed spheres,
// one for a monomer): in place, reading a list costs no pointer chase to a separate
// allocation, and a gas of a million monomers does not make a million small allocations.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>
#include <utility>

namespace ballagg {

// Align: the alignment of the whole (a 64-byte list aligned to 64 is one cache line).
template <class T, int N, std::size_t Align = alignof(T*)>
class alignas(Align) SmallVector {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  SmallVector() = default;
  SmallVector(const SmallVector& o) { append(o.data(), o.size_); }
  SmallVector(SmallVector&& o) noexcept { take(o); }
  SmallVector& operator=(const SmallVector& o) {
    if (this != &o) {
      clear();
      append(o.data(), o.size_);
    }
    return *this;
  }
  SmallVector& operator=(SmallVector&& o) noexcept {
    if (this != &o) {
      release();
      take(o);
    }
    return *this;
  }
  ~SmallVector() { release(); }

  std::int32_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T* data() { return spilled() ? heap_ : in_place_; }
  const T* data() const { return spilled() ? heap_ : in_place_; }
  T& operator[](std::int32_t k) { return data()[k]; }
  const T& operator[](std::int32_t k) const { return data()[k]; }
  const T& front() const { return data()[0]; }
  T& back() { return data()[size_ - 1]; }
  const T& back() const { return data()[size_ - 1]; }
  T* begin() { return data(); }
  T* end() { return data() + size_; }
  const T* begin() const { return data(); }
  const T* end() const { return data() + size_; }
  operator std::span<const T>() const { return {data(), static_cast<std::size_t>(size_)}; }

  void push_back(const T& v) {
    if (size_ == capacity_) grow();
    data()[size_++] = v;
  }
  void pop_back() { --size_; }
  void clear() { size_ = 0; }  // keeps any heap storage, as std::vector does

 private:
  bool spilled() const { return capacity_ > N; }
  void grow() {
    const std::int32_t capacity = 2 * capacity_;
    T* heap = new T[capacity];
    std::memcpy(heap, data(), sizeof(T) * size_);
    release();
    heap_ = heap;
    capacity_ = capacity;
  }
  void append(const T* v, std::int32_t n) {
    for (std::int32_t k = 0; k < n; ++k) push_back(v[k]);
  }
  void release() {
    if (spilled()) delete[] heap_;
    capacity_ = N;
  }
  void take(SmallVector& o) {
    size_ = o.size_;
    capacity_ = o.capacity_;
    if (o.spilled()) heap_ = o.heap_;
    else std::memcpy(in_place_, o.in_place_, sizeof(T) * o.size_);
    o.size_ = 0;
    o.capacity_ = N;
  }

  std::int32_t size_ = 0;
  std::int32_t capacity_ = N;  // N while in place
  union {
    T in_place_[N];
    T* heap_;
  };
};

}  // namespace ballagg
