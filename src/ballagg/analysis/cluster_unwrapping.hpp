#pragma once
// Which spheres form each cluster, and the cluster shapes with periodic images undone.
//
// A state file folds every centre into the box, so in a periodic box a cluster that
// straddles a face is cut into pieces on opposite sides. Shapes (gyration tensor, R_max,
// mass-radius) need the cluster in one piece: it is rebuilt along chains of near spheres
// (closer than kUnwrapReach contact distances, and than half the box), where the minimum
// image is the true separation. A cluster that wraps around the box onto itself (a chain
// that comes back shifted by a box length) has no unwrapped shape: it is flagged
// `percolating` and its shape indicators describe one arbitrary unrolling.
#include <cstdint>
#include <span>
#include <vector>

#include "ballagg/core/vec.hpp"
#include "ballagg/spatial/box.hpp"

namespace ballagg {

// Chain reach, in units of the contact distance R_i + R_j: 2, as for glued clusters in
// input files (initial_state.cpp); sticking spheres touch at 1 (within round-off).
inline constexpr double kUnwrapReach = 2.0;

struct ClusterPartition {
  std::vector<std::int32_t> label;    // per sphere: its cluster, 0 ... M-1 in order of first sphere
  std::vector<std::int32_t> start;    // per cluster c: its members are members[start[c] .. start[c+1])
  std::vector<std::int32_t> members;  // sphere ids grouped by cluster, ascending in each

  int n_clusters() const { return static_cast<int>(start.size()) - 1; }
  int size(int c) const { return start[c + 1] - start[c]; }
  std::span<const std::int32_t> members_of(int c) const {
    return {members.data() + start[c], static_cast<std::size_t>(size(c))};
  }
};

// Clusters from per-sphere labels (any integers; equal labels = one cluster). Without
// labels (an empty vector) every one of the n spheres is its own cluster.
ClusterPartition partition_clusters(const std::vector<std::int64_t>& labels, int n);

template <int D>
struct UnwrappedClusters {
  std::vector<Vec<D>> position;    // per sphere: centre with its cluster in one piece
  std::vector<char> percolating;   // per cluster: wraps around a periodic box
};

// With walls the positions are returned unchanged. In a periodic box each cluster is put
// in one piece and then shifted by whole box lengths so that its centroid lies in the box.
template <int D>
UnwrappedClusters<D> unwrap_clusters(const Box<D>& box, const std::vector<Vec<D>>& position,
                                     const std::vector<double>& radius, const ClusterPartition& clusters);

extern template UnwrappedClusters<2> unwrap_clusters<2>(const Box<2>&, const std::vector<Vec<2>>&,
                                                        const std::vector<double>&, const ClusterPartition&);
extern template UnwrappedClusters<3> unwrap_clusters<3>(const Box<3>&, const std::vector<Vec<3>>&,
                                                        const std::vector<double>&, const ClusterPartition&);

}  // namespace ballagg
