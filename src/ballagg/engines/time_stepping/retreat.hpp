#pragma once
// The fall-back of the time-stepping engine when a group's minimisation does not converge
// within max_iterations (typically a sphere that flew deep into a pocket of another
// cluster, where no nearby configuration is free of overlaps, so no local method can
// succeed) and none of its clusters has moved yet in this step: the group is moved back in
// time along this step's free flight to the latest instant at which it overlaps nothing —
// neither itself nor the spheres around it, which stay where they are. This is the
// event-driven answer for that group. (A group with clusters moved or formed in this step
// is repaired by push_apart instead: where their flight started is no longer free.)
//
// Each pair's overlap along the retreat is a quadratic in the retreat fraction theta, so
// the instants to avoid are a union of intervals, found exactly (no bisection).
#include "ballagg/engines/time_stepping/minimisation_problem.hpp"

namespace ballagg {

// Relative overlap, 1 - d / (R_i + R_j), that a retreat may leave between two spheres.
// Half of eps_c: the pairs left touching count as contacts (within eps_c) when the step
// ends.
inline double retreat_tolerance(const DahaParameters& p) { return 0.5 * p.eps_c; }

// The group's clusters moved back by the fraction theta in [0, 1] of their flight (theta =
// 1: where they were at the start of the step), theta the smallest value at which
// no pair of the group, and no pair of a sphere of the group with a sphere outside it,
// overlaps by more than retreat_tolerance (pairs that overlapped more at the start of the
// step are held to that). When no such theta exists (spheres from outside have moved into
// the group's starting place) the group returns to its start, theta = 1; the overlaps with
// those spheres are new contacts for the next round of (3.1)-(3.2).
//
// Spheres of the group's largest cluster, when it is not small, are not checked against
// spheres outside the group (see for_each_neighbour_of_group).
template <int D>
GroupSolution<D> place_at_contact(const ProblemContext<D>& ctx, const CollisionGroup& group);

extern template GroupSolution<2> place_at_contact<2>(const ProblemContext<2>&, const CollisionGroup&);
extern template GroupSolution<3> place_at_contact<3>(const ProblemContext<3>&, const CollisionGroup&);

}  // namespace ballagg
