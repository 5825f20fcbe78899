#include "ballagg/analysis/cluster_unwrapping.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {

template <int D>
UnwrappedClusters<D> unwrap_clusters(const Box<D>& box, const std::vector<Vec<D>>& x,
                                     const std::vector<double>& radius, const ClusterPartition& clusters) {
  const int n = static_cast<int>(x.size());
  UnwrappedClusters<D> out;
  out.position = x;
  out.percolating.assign(clusters.n_clusters(), 0);
  if (!box.periodic() || n == 0) return out;

  const double max_radius = *std::max_element(radius.begin(), radius.end());
  SortedCellList<D> cells(box, kUnwrapReach * 2.0 * max_radius, n);
  cells.build(x);
  const double half = 0.5 * box.length;
  std::vector<char> placed(n, 0);
  std::vector<std::int32_t> queue;
  for (int c = 0; c < clusters.n_clusters(); ++c) {
    const std::span<const std::int32_t> group = clusters.members_of(c);
    queue.assign(1, group.front());
    placed[group.front()] = 1;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int s = queue[head];
      cells.for_each_near(x[s], [&](int j) {
        if (j == s || clusters.label[j] != c) return;
        const Vec<D> d = box.separation(x[j], x[s]);
        const double r = d.norm();
        if (r >= kUnwrapReach * (radius[s] + radius[j]) || r >= half) return;
        const Vec<D> here = out.position[s] + d;
        if (placed[j]) {
          // Reached again along another chain: a box length away means it wraps around.
          if ((out.position[j] - here).cwiseAbs().maxCoeff() > half) out.percolating[c] = 1;
          return;
        }
        out.position[j] = here;
        placed[j] = 1;
        queue.push_back(j);
      });
    }
    // Members no chain reaches (a glued cluster whose links stretched, in the time-stepping
    // models that deform clusters): each joins its nearest placed member, by minimum image.
    if (queue.size() < group.size()) {
      for (int j : group) {
        if (placed[j]) continue;
        double best = std::numeric_limits<double>::infinity();
        Vec<D> at = x[j];
        for (int s : queue) {
          const Vec<D> d = box.separation(x[j], x[s]);
          if (d.squaredNorm() < best) best = d.squaredNorm(), at = out.position[s] + d;
        }
        out.position[j] = at;
        placed[j] = 1;
        queue.push_back(j);
      }
    }
    // Whole periods that bring the centroid into [0, L).
    Vec<D> centroid = Vec<D>::Zero();
    for (int j : group) centroid += out.position[j];
    centroid /= static_cast<double>(group.size());
    Vec<D> shift;
    for (int a = 0; a < D; ++a) shift[a] = -box.length * std::floor(centroid[a] / box.length);
    for (int j : group) out.position[j] += shift;
  }
  return out;
}

template UnwrappedClusters<2> unwrap_clusters<2>(const Box<2>&, const std::vector<Vec<2>>&, const std::vector<double>&,
                                                 const ClusterPartition&);
template UnwrappedClusters<3> unwrap_clusters<3>(const Box<3>&, const std::vector<Vec<3>>&, const std::vector<double>&,
                                                 const ClusterPartition&);

}  // namespace ballagg
