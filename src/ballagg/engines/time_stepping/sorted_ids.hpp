#pragma once
// Sorting lists of sphere or cluster ids and dropping repeats, as the engine's stages hand
// them on (moved spheres, retreating clusters, pairs found from both ends).
#include <algorithm>
#include <bit>
#include <cstdint>
#include <functional>
#include <vector>

namespace ballagg {

// Lists of sphere ids longer than (number of spheres) / kIdsPerBitmapWord are sorted
// through a bitmap (sort_unique_ids): reading it back costs one word per 64 spheres.
inline constexpr std::size_t kIdsPerBitmapWord = 64;

// Sorts and removes repeats.
template <class T, class Less = std::less<T>>
void sort_unique(std::vector<T>& v, Less less = {}) {
  std::sort(v.begin(), v.end(), less);
  v.erase(std::unique(v.begin(), v.end(), [&](const T& a, const T& b) { return !less(a, b) && !less(b, a); }),
          v.end());
}

// Sorts and removes repeats from a list of ids below n. A long list (a round that moves
// whole large clusters) is marked in a bitmap and read back in order, O(n / 64 + size)
// instead of a sort; the result is the same.
inline void sort_unique_ids(std::vector<int>& ids, int n) {
  if (ids.size() < static_cast<std::size_t>(n) / kIdsPerBitmapWord) {
    sort_unique(ids);
    return;
  }
  std::vector<std::uint64_t> bits((static_cast<std::size_t>(n) + 63) / 64, 0);
  for (int i : ids) bits[static_cast<std::size_t>(i) >> 6] |= std::uint64_t{1} << (i & 63);
  ids.clear();
  for (std::size_t w = 0; w < bits.size(); ++w)
    for (std::uint64_t word = bits[w]; word != 0; word &= word - 1)
      ids.push_back(static_cast<int>(64 * w) + std::countr_zero(word));
}

}  // namespace ballagg
