#include "ballagg/render/colours.hpp"

#include <algorithm>
#include <numeric>

#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {

// Red for the largest; then Tableau-like colours without red, pink or grey, dark ones
// first and their light partners after (a hash picks among all twelve).
const std::array<Rgb, kPaletteSize + 1> kClusterColours{{
    {0.839, 0.153, 0.157},  // red: the largest cluster
    {0.122, 0.467, 0.706},  // blue
    {1.000, 0.498, 0.055},  // orange
    {0.173, 0.627, 0.173},  // green
    {0.580, 0.404, 0.741},  // purple
    {0.549, 0.337, 0.294},  // brown
    {0.090, 0.745, 0.812},  // cyan
    {0.737, 0.741, 0.133},  // olive
    {0.443, 0.620, 0.851},  // light blue
    {0.988, 0.706, 0.392},  // light orange
    {0.494, 0.800, 0.447},  // light green
    {0.753, 0.639, 0.851},  // lavender
    {0.110, 0.310, 0.380},  // dark teal
}};

namespace {

// A well-mixed 32-bit hash (the finaliser of MurmurHash3), so that neighbouring ids get
// unrelated colours.
std::uint32_t mix(std::uint32_t h) {
  h ^= h >> 16;
  h *= 0x85ebca6bu;
  h ^= h >> 13;
  h *= 0xc2b2ae35u;
  h ^= h >> 16;
  return h;
}

// Pairs (a, b), a < b, of cluster labels with spheres within the gap of each other, as
// adjacency lists (compressed rows).
template <int D>
void neighbour_lists(const Frame<D>& f, const Particles<D>& p, std::vector<std::int32_t>& start,
                     std::vector<std::int32_t>& list) {
  const int n = f.size();
  const double max_r = *std::max_element(p.radius.begin(), p.radius.end());
  const double gap = kNeighbourGap * std::accumulate(p.radius.begin(), p.radius.end(), 0.0) / n;
  SortedCellList<D> cells(p.box, 2.0 * max_r + gap, n);
  cells.build(f.position);
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  for (int i = 0; i < n; ++i) {
    const std::int32_t ci = f.cluster[i];
    cells.for_each_near(f.position[i], [&](std::int32_t j) {
      const std::int32_t cj = f.cluster[j];
      if (cj <= ci) return;
      const double reach = p.radius[i] + p.radius[j] + gap;
      if (p.box.separation(f.position[i], f.position[j]).squaredNorm() < reach * reach) pairs.emplace_back(ci, cj);
    });
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  const int n_labels = f.cluster.empty() ? 0 : *std::max_element(f.cluster.begin(), f.cluster.end()) + 1;
  // Each label's list holds its smaller neighbours: those coloured before it.
  start.assign(n_labels + 1, 0);
  for (const auto& [a, b] : pairs) ++start[b + 1];
  for (int l = 0; l < n_labels; ++l) start[l + 1] += start[l];
  list.resize(pairs.size());
  std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
  for (const auto& [a, b] : pairs) list[fill[b]++] = a;
}

}  // namespace

template <int D>
std::vector<std::uint8_t> cluster_colours(const Frame<D>& f, const Particles<D>& p, int largest_label) {
  const int n = f.size();
  if (n == 0) return {};
  // Labels follow the first sphere of each cluster, so the first sphere's id is a key
  // that survives merges (the survivor keeps the smaller one) and relabelling.
  const int n_labels = *std::max_element(f.cluster.begin(), f.cluster.end()) + 1;
  std::vector<std::int32_t> first(n_labels, -1);
  for (int i = 0; i < n; ++i)
    if (first[f.cluster[i]] < 0) first[f.cluster[i]] = i;
  std::vector<std::int32_t> start, smaller;
  neighbour_lists(f, p, start, smaller);
  std::vector<std::uint8_t> colour(n_labels, 0);
  for (int l = 0; l < n_labels; ++l) {
    if (l == largest_label) continue;
    std::array<bool, kPaletteSize + 1> taken{};
    for (std::int32_t k = start[l]; k < start[l + 1]; ++k) taken[colour[smaller[k]]] = true;
    const int preferred = static_cast<int>(mix(static_cast<std::uint32_t>(first[l])) % kPaletteSize);
    int pick = preferred;
    for (int step = 0; step < kPaletteSize; ++step) {
      const int candidate = (preferred + step) % kPaletteSize;
      if (!taken[candidate + 1]) { pick = candidate; break; }
    }
    colour[l] = static_cast<std::uint8_t>(pick + 1);
  }
  std::vector<std::uint8_t> per_sphere(n);
  for (int i = 0; i < n; ++i) per_sphere[i] = colour[f.cluster[i]];
  return per_sphere;
}

template std::vector<std::uint8_t> cluster_colours<2>(const Frame<2>&, const Particles<2>&, int);
template std::vector<std::uint8_t> cluster_colours<3>(const Frame<3>&, const Particles<3>&, int);

}  // namespace ballagg
