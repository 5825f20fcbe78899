#pragma once
// The order of points along a Z-order (Morton) curve over the box: generated spheres are
// numbered in this order rather than in the order they were placed, since their numbering
// carries no meaning and neighbours that sit close in memory make the engines much less
// bound by cache misses (docs/profiles.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

// Interleaves the bits of cell coordinates: cells close in space get close numbers.
template <int D>
std::uint64_t z_order_key(const std::array<std::uint32_t, D>& cell) {
  std::uint64_t key = 0;
  for (int bit = 0; bit < 64 / D; ++bit)
    for (int a = 0; a < D; ++a) key |= static_cast<std::uint64_t>((cell[a] >> bit) & 1u) << (bit * D + a);
  return key;
}

// order[k]: the index of the k-th point along the curve (ties by index).
template <int D>
std::vector<std::size_t> z_order(const std::vector<Vec<D>>& x, const Box<D>& box) {
  const auto side = static_cast<std::uint32_t>(std::max(1.0, std::ceil(std::pow(static_cast<double>(x.size()), 1.0 / D))));
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::array<std::uint32_t, D> cell;
    for (int a = 0; a < D; ++a)
      cell[a] = std::min(side - 1, static_cast<std::uint32_t>(std::max(0.0, x[i][a] / box.length * side)));
    keyed[i] = {z_order_key<D>(cell), i};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::size_t> order(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) order[k] = keyed[k].second;
  return order;
}

}  // namespace ballagg
