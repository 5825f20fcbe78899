#pragma once
// Cluster colours: the largest cluster in red, every other cluster in one of a palette of
// colours that read well on white and are told apart from red and from each other. Each
// cluster prefers the palette entry picked by a hash of its first sphere's id, so a
// cluster keeps its colour from frame to frame of a video; a cluster whose preferred
// colour is already taken by a neighbour (one closer than kNeighbourGap) takes the next
// free one, so that touching clusters never share a colour while the palette lasts.
#include <array>
#include <cstdint>
#include <vector>

#include "ballagg/io/frame.hpp"

namespace ballagg {

struct Rgb {
  double r = 0, g = 0, b = 0;  // in [0, 1]
};

// Colour 0 is the largest cluster's; 1 ... kPaletteSize the others'.
inline constexpr int kPaletteSize = 12;
extern const std::array<Rgb, kPaletteSize + 1> kClusterColours;
inline constexpr Rgb kBackground{1.0, 1.0, 1.0};

// Two clusters are neighbours when two of their spheres are closer than this many mean
// radii (surface to surface): nearly touching clusters must look different too.
inline constexpr double kNeighbourGap = 1.0;

// Per sphere, its index into kClusterColours. `largest_label` is the cluster drawn red.
template <int D>
std::vector<std::uint8_t> cluster_colours(const Frame<D>& frame, const Particles<D>& particles, int largest_label);

}  // namespace ballagg
