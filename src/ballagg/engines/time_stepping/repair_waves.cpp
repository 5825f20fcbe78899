#include "ballagg/engines/time_stepping/repair_waves.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "ballagg/core/parallel.hpp"

namespace ballagg {
namespace {

// At most this many tiles in all (2^16: 256 x 256 in 2D, 40^3 in 3D): the grid is cleared
// once per call, so it stays small next to the repairs it orders.
constexpr double kMaxTiles = 65536.0;

// Regions of at least this many groups are found on several threads (a region reads the
// spheres of its group at scattered places: worth sharing from a few dozen groups).
constexpr std::int64_t kParallelRegions = 64;

// Tiles across a typical region (the median width): finer tiles tell more regions apart,
// so fewer waves, at (kTilesPerRegion + 1)^D tiles marked per region.
constexpr double kTilesPerRegion = 4.0;

// Where the group's spheres are now and where free flight put them, widened by twice the
// group's longest flight and by two contact distances (one is enough; the second leaves
// round-off no say).
template <int D>
Region<D> region_of(const StepView<D>& ctx, const CollisionGroup& g) {
  const State<D>& s = ctx.state;
  const auto clusters = clusters_of_group(ctx, g);
  const Vec<D> origin = ctx.positions[s.clusters[clusters.front().first].members.front()];
  constexpr double inf = std::numeric_limits<double>::infinity();
  Region<D> r{Vec<D>::Constant(inf), Vec<D>::Constant(-inf)};
  auto include = [&](const Vec<D>& x) {
    const Vec<D> unfolded = origin + s.box.separation(x, origin);
    r.lo = r.lo.cwiseMin(unfolded);
    r.hi = r.hi.cwiseMax(unfolded);
  };
  double longest_flight = 0.0;
  for (const auto& [c, b] : clusters) {
    longest_flight = std::max(longest_flight, ctx.flight[c].norm());
    for (int i : s.clusters[c].members) {
      include(ctx.positions[i]);
      include(Vec<D>(ctx.positions[i] - ctx.step_shift[i]));
    }
  }
  const double margin = 2.0 * longest_flight + 2.0 * 2.0 * s.max_radius() * (1.0 + ctx.settings.daha.eps_c);
  r.lo.array() -= margin;
  r.hi.array() += margin;
  return r;
}

// The tiles of a grid of n per axis over a box of side length that a region covers, per
// axis a range [first, last] (folded modulo n in a periodic box, clamped to the grid
// between walls).
template <int D>
std::array<std::array<int, 2>, D> tile_ranges(const Region<D>& r, int n, double length, bool periodic) {
  std::array<std::array<int, 2>, D> out;
  const double side = length / n;
  for (int a = 0; a < D; ++a) {
    const double first = std::floor(r.lo[a] / side), last = std::floor(r.hi[a] / side);
    if (periodic) {
      out[a] = last - first + 1 >= n ? std::array<int, 2>{0, n - 1}
                                      : std::array<int, 2>{static_cast<int>(first), static_cast<int>(last)};
    } else {
      out[a] = {static_cast<int>(std::clamp(first, 0.0, n - 1.0)), static_cast<int>(std::clamp(last, 0.0, n - 1.0))};
    }
  }
  return out;
}

// Calls f(tile) for every tile of the ranges (indices folded into the grid).
template <int D, class F>
void for_each_tile(const std::array<std::array<int, 2>, D>& ranges, int n, F&& f) {
  std::array<int, D> at;
  for (int a = 0; a < D; ++a) at[a] = ranges[a][0];
  while (true) {
    std::size_t tile = 0;
    for (int a = D - 1; a >= 0; --a) tile = tile * n + static_cast<std::size_t>(((at[a] % n) + n) % n);
    f(tile);
    int a = 0;
    while (a < D && at[a] == ranges[a][1]) {
      at[a] = ranges[a][0];
      ++a;
    }
    if (a == D) return;
    ++at[a];
  }
}

// A bijective scramble of 64-bit words (the finaliser of splitmix64): neighbouring ids go
// to unrelated values.
std::uint64_t scramble(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// The order of the repairs: by the scrambled id of each group's first body (groups are
// disjoint, so the ids differ).
std::vector<std::size_t> repair_order(const std::vector<CollisionGroup>& groups, const std::vector<std::size_t>& failed) {
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed;
  for (std::size_t k : failed) keyed.push_back({scramble(static_cast<std::uint64_t>(groups[k].bodies.front())), k});
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::size_t> out;
  for (const auto& [key, k] : keyed) out.push_back(k);
  return out;
}

}  // namespace

template <int D>
std::vector<std::vector<std::size_t>> waves_of_regions(const std::vector<Region<D>>& regions, const Box<D>& box) {
  if (regions.empty()) return {};
  // Tiles a quarter of a typical region wide: a region covers about 5^D of them, and two
  // regions share a tile only when they come within a quarter of a region of each other.
  std::vector<double> widths;
  for (const Region<D>& r : regions) widths.push_back((r.hi - r.lo).maxCoeff());
  std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
  const double typical = widths[widths.size() / 2];
  const double most_per_axis = std::floor(std::pow(kMaxTiles, 1.0 / D));
  const int n = typical > 0.0 ? static_cast<int>(std::clamp(std::floor(kTilesPerRegion * box.length / typical), 1.0, most_per_axis))
                              : static_cast<int>(most_per_axis);
  std::size_t n_tiles = 1;
  for (int a = 0; a < D; ++a) n_tiles *= static_cast<std::size_t>(n);
  std::vector<int> last_wave(n_tiles, -1);  // per tile: the last wave of a region covering it
  std::vector<std::vector<std::size_t>> waves;
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const auto ranges = tile_ranges<D>(regions[k], n, box.length, box.periodic());
    int wave = 0;
    for_each_tile<D>(ranges, n, [&](std::size_t t) { wave = std::max(wave, last_wave[t] + 1); });
    for_each_tile<D>(ranges, n, [&](std::size_t t) { last_wave[t] = wave; });
    if (wave == static_cast<int>(waves.size())) waves.emplace_back();
    waves[wave].push_back(k);
  }
  return waves;
}

template <int D>
std::vector<std::vector<std::size_t>> repair_waves(const StepView<D>& ctx, const std::vector<CollisionGroup>& groups,
                                                   const std::vector<std::size_t>& unsolved) {
  if (unsolved.size() <= 1) {
    if (unsolved.empty()) return {};
    return {unsolved};
  }
  const std::vector<std::size_t> order = repair_order(groups, unsolved);
  // A region reads every sphere of its group's clusters, twice, and a round may have
  // thousands of groups to repair. Each region is its own, so they are found at once.
  const std::int64_t n = static_cast<std::int64_t>(order.size());
  std::vector<Region<D>> regions(order.size());
#pragma omp parallel for schedule(dynamic, 16) if (n >= kParallelRegions)
  for (std::int64_t k = 0; k < n; ++k) regions[k] = region_of(ctx, groups[order[k]]);
  std::vector<std::vector<std::size_t>> waves = waves_of_regions(regions, ctx.state.box);
  for (std::vector<std::size_t>& wave : waves)
    for (std::size_t& k : wave) k = order[k];
  return waves;
}

template std::vector<std::vector<std::size_t>> waves_of_regions<2>(const std::vector<Region<2>>&, const Box<2>&);
template std::vector<std::vector<std::size_t>> waves_of_regions<3>(const std::vector<Region<3>>&, const Box<3>&);
template std::vector<std::vector<std::size_t>> repair_waves<2>(const StepView<2>&, const std::vector<CollisionGroup>&,
                                                               const std::vector<std::size_t>&);
template std::vector<std::vector<std::size_t>> repair_waves<3>(const StepView<3>&, const std::vector<CollisionGroup>&,
                                                               const std::vector<std::size_t>&);

}  // namespace ballagg
