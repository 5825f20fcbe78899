#pragma once
// Clusters with periodic images undone.
//
// A state file folds every centre into the box, so in a periodic box a cluster that
// straddles a face is cut into pieces on opposite sides. Shapes (gyration tensor, R_max,
// mass-radius) need the cluster in one piece: it is rebuilt along chains of near spheres
// (closer than kUnwrapReach contact distances, and than half the box), where the minimum
// image is the true separation. A cluster that wraps around the box onto itself (a chain
// that comes back shifted by a box length) has no unwrapped shape: it is flagged
// `percolating` and its shape indicators describe one arbitrary unrolling.
#include <vector>

#include "ballagg/analysis/cluster_partition.hpp"
#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

// Chain reach, in units of the contact distance R_i + R_j: 2, as for glued clusters in
// input files (initial_state.cpp); sticking spheres touch at 1 (within round-off).
inline constexpr double kUnwrapReach = 2.0;

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
