#include "ballagg/render/scene.hpp"

#include <numeric>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"

namespace ballagg {

template <int D>
Scene<D> make_scene(const Frame<D>& f, const Particles<D>& p, int rank) {
  Scene<D> s;
  s.box = p.box;
  s.time = f.time;
  s.n_spheres = f.size();
  s.n_clusters = f.cluster.empty() ? 0 : *std::max_element(f.cluster.begin(), f.cluster.end()) + 1;
  const int largest = kth_largest_cluster(f.cluster, 1);
  s.largest = static_cast<int>(std::count(f.cluster.begin(), f.cluster.end(), largest));
  s.mean_radius = std::accumulate(p.radius.begin(), p.radius.end(), 0.0) / std::max(1, p.size());
  if (rank <= 0) {
    s.centre = f.position;
    s.radius = p.radius;
    s.colour = cluster_colours(f, p, largest);
    s.lo = Vec<D>::Zero();
    s.hi = Vec<D>::Constant(p.box.length);
    return s;
  }
  const int label = kth_largest_cluster(f.cluster, rank);
  if (label < 0)
    throw InputError(fmt::format("--aggregate {}: there are only {} clusters at t = {}", rank, s.n_clusters, f.time));
  s.whole_box = false;
  s.aggregate_rank = rank;
  s.lo = Vec<D>::Constant(1e300);
  s.hi = Vec<D>::Constant(-1e300);
  for (int i = 0; i < f.size(); ++i) {
    if (f.cluster[i] != label) continue;
    const Vec<D> x = f.unwrapped(i, p.box.length);
    s.centre.push_back(x);
    s.radius.push_back(p.radius[i]);
    s.lo = s.lo.cwiseMin(x - Vec<D>::Constant(p.radius[i]));
    s.hi = s.hi.cwiseMax(x + Vec<D>::Constant(p.radius[i]));
  }
  s.shown_cluster_size = s.size();
  s.colour.assign(s.size(), rank == 1 ? 0 : 1);  // red if it is the largest
  return s;
}

template Scene<2> make_scene<2>(const Frame<2>&, const Particles<2>&, int);
template Scene<3> make_scene<3>(const Frame<3>&, const Particles<3>&, int);

}  // namespace ballagg
