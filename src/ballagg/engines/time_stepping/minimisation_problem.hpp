#pragma once
// Turns one connected group of colliding clusters into a DAHA problem (daha.hpp), for each
// cluster model, and reads the solution back as sphere displacements.
//
// rigid        variables: the old clusters; pairs: the adhesive set S of this step.
// non-rigid    variables: every sphere; pairs: S plus the old links of the clusters, all
//              attracting (potential (3.5)) and constrained.
// almost-rigid variables: every sphere; pairs: every pair closer than Delta_W (plus a
//              margin), found on a grid of cells ("rectangles") of side Delta_W whose
//              number grows with the number of spheres; attracting while within Delta_W
//              (3.30), all constrained (3.31).
#include <cstdint>
#include <vector>

#include "ballagg/core/state.hpp"
#include "ballagg/engines/time_stepping/adhesive_links.hpp"
#include "ballagg/engines/time_stepping/daha.hpp"
#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {

struct SpherePair {
  std::int32_t i, j;    // sphere ids, i < j
  double lambda;        // multiplier of its constraint (0: not set yet, (3.26) applies)
  bool active = true;   // false once a fall-back placement replaced it
};

// One connected group: the old clusters and the pairs of S that join them.
struct CollisionGroup {
  std::vector<std::int32_t> clusters;  // sorted
  std::vector<std::int32_t> pairs;     // indices into S
};

template <int D>
struct GroupSolution {
  std::vector<std::int32_t> spheres;   // moved spheres
  std::vector<Vec<D>> shift;           // their displacements (box units)
  std::vector<double> pair_lambda;     // final multipliers of the group's pairs of S
  std::vector<SpherePair> old_links;   // non-rigid / almost-rigid: old links, new multipliers
  DahaResult result;
  int n_variables = 0;
  double link_stretch = 0.0;           // largest d / sigma - 1 over the old links (non-rigid models)
  bool placed_at_contact = false;      // minimisation abandoned, group moved back to first contact
  std::vector<SpherePair> contacts;    // then: the touching pairs that replace the group's S pairs
};

// Everything the builder reads; shared by all groups of a step (read-only).
template <int D>
struct ProblemContext {
  const State<D>& state;
  const std::vector<Vec<D>>& positions;  // current sphere centres (folded into the box)
  const std::vector<Vec<D>>& step_shift; // how far the minimisations of this step moved them
  const std::vector<Vec<D>>& flight;     // per cluster: how far this step's free flight moved it
  const SortedCellList<D>& cells;        // every sphere, binned at most cell_slack from `positions`
  double cell_slack;
  const std::vector<SpherePair>& S;
  const AdhesiveLinks& links;
  const TimeSteppingSettings& settings;
  double length_scale;                   // mean contact distance 2 <R>
  double delta_w;                        // resolved Delta_W
  double mean_mass;
};

// Where the group's spheres start: their current centres, or (backtrack) where free flight
// put them moved back by the fraction `retreat` of this step's flight.
struct GroupStart {
  bool backtrack = false;
  double retreat = 0.0;
};

// The fall-back when no minimisation converges: moves the group's old clusters back along
// their velocities to the latest instant of the step where no two of them overlap by more
// than eps_c / 2 (bisection), and links the pairs that touch there.
template <int D>
GroupSolution<D> place_at_contact(const ProblemContext<D>& ctx, const CollisionGroup& group);

template <int D>
GroupSolution<D> solve_group(const ProblemContext<D>& ctx, const CollisionGroup& group, GroupStart start = {});

extern template GroupSolution<2> solve_group<2>(const ProblemContext<2>&, const CollisionGroup&, GroupStart);
extern template GroupSolution<3> solve_group<3>(const ProblemContext<3>&, const CollisionGroup&, GroupStart);
extern template GroupSolution<2> place_at_contact<2>(const ProblemContext<2>&, const CollisionGroup&);
extern template GroupSolution<3> place_at_contact<3>(const ProblemContext<3>&, const CollisionGroup&);

}  // namespace ballagg
