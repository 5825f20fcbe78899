#pragma once
// Turns one connected group of colliding clusters into a DAHA problem (daha.hpp), for each
// cluster model, and reads the solution back as sphere displacements.
//
// A group is a set of bodies (the clusters of the step joined by the links of its earlier
// rounds, step_bodies.hpp) and the pairs of S that join them.
//
// rigid        variables: the bodies; pairs: the adhesive set S of this round, and guards
//              (constrained neighbours, see add_guards).
// non-rigid    variables: every sphere; pairs: S plus the links of the clusters, all
//              attracting (potential (3.5)) and constrained.
// almost-rigid variables: every sphere; pairs: every pair closer than Delta_W (plus a
//              margin), found on a grid of cells ("rectangles") of side Delta_W whose
//              number grows with the number of spheres; attracting while within Delta_W
//              (3.30), all constrained (3.31).
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "ballagg/core/state.hpp"
#include "ballagg/engines/time_stepping/adhesive_links.hpp"
#include "ballagg/engines/time_stepping/adhesive_set.hpp"
#include "ballagg/engines/time_stepping/daha.hpp"
#include "ballagg/engines/time_stepping/group_marks.hpp"
#include "ballagg/engines/time_stepping/step_bodies.hpp"
#include "ballagg/engines/time_stepping/step_view.hpp"
#include "ballagg/spatial/movable_cell_list.hpp"

namespace ballagg {

template <int D>
struct GroupSolution {
  std::vector<std::int32_t> spheres;   // moved spheres
  std::vector<Vec<D>> shift;           // their displacements (box units)
  std::vector<SpherePair> old_links;   // non-rigid / almost-rigid: old links, new multipliers
  DahaResult result;
  int n_variables = 0;
  double link_stretch = 0.0;           // largest d / sigma - 1 over the old links (non-rigid models)
  bool placed_at_contact = false;      // minimisation abandoned, group moved back to first contact
  bool dissolves_bodies = false;       // the solution undoes the links of the group's bodies
  std::vector<SpherePair> contacts;    // pairs touching in the solution: the new links

  // Frees the moves of a solution that is not applied (a failed minimisation, the retreat
  // a flight sweep starts from): at the end of a large run they are those of a giant's
  // every sphere, held while the solution that replaces them is built.
  void release_moves() {
    std::vector<std::int32_t>().swap(spheres);
    std::vector<Vec<D>>().swap(shift);
  }
};

template <int D>
GroupSolution<D> solve_group(const StepView<D>& ctx, const CollisionGroup& group);

// The clusters of a group's bodies, each with the index of its body in group.bodies,
// in the order of the bodies.
template <int D>
std::vector<std::pair<std::int32_t, std::int32_t>> clusters_of_group(const StepView<D>& ctx,
                                                                     const CollisionGroup& g) {
  std::vector<std::pair<std::int32_t, std::int32_t>> out;
  for (std::size_t b = 0; b < g.bodies.size(); ++b)
    for (int c : ctx.bodies.clusters_of(g.bodies[b])) out.push_back({c, static_cast<std::int32_t>(b)});
  return out;
}

// The index in group.bodies of the body of sphere i, or -1 when it is not in the group.
template <int D>
int body_index(const StepView<D>& ctx, const CollisionGroup& g, int i) {
  const int body = ctx.bodies.body_of(ctx.state.spheres.cluster[i]);
  const auto it = std::lower_bound(g.bodies.begin(), g.bodies.end(), body);
  return it != g.bodies.end() && *it == body ? static_cast<int>(it - g.bodies.begin()) : -1;
}

// Clusters of up to this many spheres are small: the neighbourhood of all their spheres is
// searched when a group is built or repaired (a larger cluster moves little in a step, as
// its speed falls with its mass, and its neighbours are found by the next round).
inline constexpr int kSmallClusterSize = 32;

// Calls f(i, j, b) for every sphere i of a queried cluster of the group's bodies and every
// sphere j of another cluster whose centre may lie within `reach` of i's; b is the index
// of j's body in the group, or -1 when it is outside. A pair of two queried clusters is
// reported once. Queried: the clusters of at most max_size spheres, except the group's
// largest cluster when it is not small. A giant aggregate hit by a monomer moves little
// (bodies move in inverse proportion to their mass) and is not queried, so that the hit
// does not cost the giant's size; its pairs with the other members are found from their
// side, and any contact it makes with spheres outside by the next round of (3.1)-(3.2).
// Which clusters of a group for_each_neighbour_of_group queries.
template <int D>
struct QueriedClusters {
  QueriedClusters(const StepView<D>& ctx, const CollisionGroup& g, int size_limit)
      : s(ctx.state), clusters(clusters_of_group(ctx, g)), largest(clusters.front().first), max_size(size_limit) {
    for (const auto& [c, b] : clusters)
      if (s.clusters[c].size() > s.clusters[largest].size()) largest = c;
  }
  bool operator()(int c) const {
    const int size = s.clusters[c].size();
    return size <= max_size && (c != largest || size <= kSmallClusterSize);
  }
  const State<D>& s;
  std::vector<std::pair<std::int32_t, std::int32_t>> clusters;  // (cluster, body index) of the group
  int largest;
  int max_size;
};

template <int D, class F>
void for_each_neighbour_of_group(const StepView<D>& ctx, const CollisionGroup& g, double reach, int max_size,
                                 F&& f) {
  const State<D>& s = ctx.state;
  const QueriedClusters<D> queried(ctx, g, max_size);
  const GroupMarks marks(s.spheres.cluster, s.clusters.size(), queried.clusters);
  for (const auto& cluster_and_body : queried.clusters) {
    const int c = cluster_and_body.first;  // not a structured binding: clang 14 cannot capture one in a lambda
    if (!queried(c)) continue;
    for (int i : s.clusters[c].members) {
      auto visit = [&](int j) {
        const int cj = s.spheres.cluster[j];
        if (cj == c) return;
        const int bj = marks.body_index(j);
        if (bj >= 0 && queried(cj) && j < i) return;
        f(i, j, bj);
      };
      // The cell list holds positions up to cell_slack from the current ones.
      ctx.cells.for_each_within(ctx.positions[i], reach + ctx.cell_slack, visit);
    }
  }
}

extern template GroupSolution<2> solve_group<2>(const StepView<2>&, const CollisionGroup&);
extern template GroupSolution<3> solve_group<3>(const StepView<3>&, const CollisionGroup&);

}  // namespace ballagg
