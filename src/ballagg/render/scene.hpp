#pragma once
// What a picture shows, independent of how it is drawn: spheres with their colours, the
// region to frame, and the facts for the caption. Either the whole box (spheres at their
// folded positions; the renderers add the periodic images of those crossing a face) or
// one aggregate, unwrapped across periodic faces and framed alone.
#include <cstdint>
#include <string>
#include <vector>

#include "ballagg/analysis/cluster_partition.hpp"
#include "ballagg/io/frame.hpp"
#include "ballagg/render/colours.hpp"

namespace ballagg {

template <int D>
struct Scene {
  Box<D> box;
  bool whole_box = true;          // false: one aggregate, no box drawn
  Vec<D> lo, hi;                  // the region framed (the box, or the aggregate's bounds)
  std::vector<Vec<D>> centre;
  std::vector<double> radius;
  std::vector<std::uint8_t> colour;  // index into kClusterColours
  // Caption.
  double time = 0.0;
  int n_spheres = 0, n_clusters = 0, largest = 0;  // of the whole system
  int shown_cluster_size = 0;     // one aggregate: its spheres
  int aggregate_rank = 0;         // one aggregate: 1 = the largest, 2 = the second, ...
  double mean_radius = 0.0;

  int size() const { return static_cast<int>(centre.size()); }
  bool periodic_images() const { return whole_box && box.periodic(); }
};

// The whole box, or (aggregate_rank >= 1) the aggregate of that rank by size. Throws
// InputError when there is no aggregate of that rank.
template <int D>
Scene<D> make_scene(const Frame<D>& frame, const Particles<D>& particles, int aggregate_rank = 0);

}  // namespace ballagg
