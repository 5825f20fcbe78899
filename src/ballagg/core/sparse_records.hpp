#pragma once
// A record of type T for some of the ids 0..n-1 (clusters of several spheres, say), behind
// a 4-byte place per id.
//
// Why: a run starts with one cluster per sphere, and a record that only aggregates need
// (a bounding box, a drift) would cost its full size for every monomer if stored per id.
// Here an id without a record costs 4 bytes, and the records sit in one dense array.
//
// Freed places are taken again last freed first, so the layout, like everything else in a
// run, depends on the order of the calls alone.
#include <cstdint>
#include <vector>

namespace ballagg {

template <class T>
class SparseRecords {
 public:
  // n ids, none with a record.
  void reset(std::size_t n) {
    place_.assign(n, kNone);
    records_.clear();
    free_.clear();
  }
  // More ids (none with a record), or fewer (the dropped ones must have none).
  void resize(std::size_t n) { place_.resize(n, kNone); }
  std::size_t ids() const { return place_.size(); }

  // Id c's record, or nullptr.
  const T* find(std::size_t c) const {
    const std::int32_t p = place_[c];
    return p >= 0 ? &records_[static_cast<std::size_t>(p)] : nullptr;
  }
  // Id c's record (created from `value` if c has none) set to `value`.
  void store(std::size_t c, const T& value) {
    std::int32_t& p = place_[c];
    if (p < 0) {
      if (free_.empty()) {
        p = static_cast<std::int32_t>(records_.size());
        records_.push_back(value);
        return;
      }
      p = free_.back();
      free_.pop_back();
    }
    records_[static_cast<std::size_t>(p)] = value;
  }
  // Drops id c's record, if any.
  void forget(std::size_t c) {
    std::int32_t& p = place_[c];
    if (p < 0) return;
    free_.push_back(p);
    p = kNone;
  }

 private:
  static constexpr std::int32_t kNone = -1;
  std::vector<std::int32_t> place_;  // per id: its record's place in records_, or kNone
  std::vector<T> records_;
  std::vector<std::int32_t> free_;   // places of dropped records
};

}  // namespace ballagg
