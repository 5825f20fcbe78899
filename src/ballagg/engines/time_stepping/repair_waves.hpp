#pragma once
// The fall-backs of one round, in waves that can run at once.
//
// The groups of a round that the minimisation did not solve are repaired (retreat.hpp,
// flight_sweep.hpp) one after the other, each seeing where the earlier repairs left their
// spheres. The first steps of a large run send thousands of groups per round to the
// fall-back, which, done so, would leave every thread but one idle.
//
// A repair touches only a neighbourhood of its group. Every cluster of the group stays
// within 2 F of where free flight put it, F the group's longest flight in the step: it goes
// back along its own flight (at most F), then on at the speed of its body, a mass-weighted
// mean of flights of the group or zero (at most F more). The repair moves only the group's
// spheres, and it reads the spheres outside only within a contact distance of those paths.
// So its region, the box around its spheres' places (where free flight put them and where
// they are now) widened by 2 F and two contact distances, holds all it reads and writes; two
// groups whose regions are disjoint cannot see each other, and repairing them in either
// order, or at once, gives the same answers.
//
// The order of the repairs is a choice: any order is one group after the other, each
// seeing the earlier ones. Group order follows the ids of the clusters, which at the
// lattice start follow the rows of the lattice: each group's region would meet the next
// one's, and the repairs would form a chain of waves of one repair each. They are taken
// instead in an order scrambled by a hash of each group's first body, in which neighbours
// seldom follow each other.
//
// repair_waves puts each group in the wave after the last wave holding a group earlier in
// that order whose region meets its own. Run wave by wave, the groups of a wave at once,
// the repairs give exactly what that order gives one after the other (so the result does
// not depend on the number of threads). Regions are compared on a coarse grid of tiles
// over the box: a group marks the tiles its region covers, O(tiles covered) per group.
#include <cstddef>
#include <vector>

#include "ballagg/engines/time_stepping/minimisation_problem.hpp"

namespace ballagg {

// A box in space; its coordinates may reach beyond [0, L) in a periodic box (a region
// unfolded around one of its points), and are then read modulo L.
template <int D>
struct Region {
  Vec<D> lo, hi;
};

// The regions taken in order, in waves: each in the wave after the last wave holding an
// earlier region that meets it. Meeting is judged on a grid of tiles over the box (two
// regions that cover a common tile meet), so regions in one wave are always disjoint.
template <int D>
std::vector<std::vector<std::size_t>> waves_of_regions(const std::vector<Region<D>>& regions, const Box<D>& box);

// The waves for the groups listed in `unsolved` (indices into groups), each wave in the
// order of the repairs.
template <int D>
std::vector<std::vector<std::size_t>> repair_waves(const StepView<D>& ctx, const std::vector<CollisionGroup>& groups,
                                                   const std::vector<std::size_t>& unsolved);

extern template std::vector<std::vector<std::size_t>> waves_of_regions<2>(const std::vector<Region<2>>&, const Box<2>&);
extern template std::vector<std::vector<std::size_t>> waves_of_regions<3>(const std::vector<Region<3>>&, const Box<3>&);
extern template std::vector<std::vector<std::size_t>> repair_waves<2>(const StepView<2>&,
                                                                      const std::vector<CollisionGroup>&,
                                                                      const std::vector<std::size_t>&);
extern template std::vector<std::vector<std::size_t>> repair_waves<3>(const StepView<3>&,
                                                                      const std::vector<CollisionGroup>&,
                                                                      const std::vector<std::size_t>&);

}  // namespace ballagg
