#pragma once
// The fall-back that keeps the flight (ts.fall_back = "keep-flight").
//
// The retreat (retreat.hpp) moves a group the minimisation did not solve back to the last
// instant of the step at which it overlaps nothing, and the rest of the step's flight is
// lost. When a step is many collision times long (dt_factor scales the step with the box,
// so a large box has steps of several diameters of flight) nearly every cluster of the box
// is in such a group at every step, a step merges about one pair per group, and the run
// needs ever more steps as N grows.
//
// Here the group goes on from that instant to the end of the step, event by event as the
// exact dynamics would: the pairs touching there join their clusters into bodies that fly
// on with the mass-weighted flight of rule (2.9); at the next contact between two bodies
// they join in the same way; a body that touches a sphere outside the group (which stays
// where it is, as in the retreat) or a wall stops there for the rest of the step. So a
// step merges what the exact dynamics merges within the group in that time, and each
// cluster ends the step where its body's flight took it.
//
// The state is not changed: the solution is a displacement per sphere, and the pairs
// joined (the contacts) become the step's links, as for any solution.
#include "ballagg/engines/time_stepping/retreat.hpp"

namespace ballagg {

template <int D>
GroupSolution<D> keep_flight(const StepView<D>& ctx, const CollisionGroup& group);

extern template GroupSolution<2> keep_flight<2>(const StepView<2>&, const CollisionGroup&);
extern template GroupSolution<3> keep_flight<3>(const StepView<3>&, const CollisionGroup&);

}  // namespace ballagg
