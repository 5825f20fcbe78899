#pragma once
// The fall-back of the time-stepping engine when a group's minimisation does not converge
// within max_iterations (typically a sphere that flew deep into a pocket of another
// cluster, where no nearby configuration is free of overlaps, so no local method can
// succeed) and none of its clusters has moved yet in this step: the group is moved back in
// time along this step's free flight to the latest instant at which it overlaps nothing —
// neither itself nor the spheres around it, which stay where they are. This is the
// event-driven answer for that group. What the step's minimisations did to the group is
// undone: its clusters go back along their flights from where free flight put them, and
// the bodies of the group are dissolved. The fall-back that keeps the flight
// (flight_sweep.hpp) goes on from the instant found here to the end of the step.
//
// Each pair's overlap along the retreat is a quadratic in the retreat fraction theta, so
// the instants to avoid are a union of intervals, found exactly (no bisection).
#include "ballagg/core/prefetch.hpp"
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
// spheres outside the group (see for_each_neighbour_of_group), nor are those of any other
// cluster of more than kOutsideSearchedClusterSize spheres.
// The spheres of a cluster of the group up to this size are listed directly as partners
// of a retreating sphere (for so few, cheaper than a search in the cell list).
inline constexpr int kListedClusterSize = 64;

// The fall-backs (this retreat and the sweep that follows it, flight_sweep.hpp) search the
// paths of a cluster's spheres for spheres outside the group only when the cluster has at
// most this many spheres. A larger cluster moves little in a step (a cluster's speed falls
// as its mass grows), so what it meets outside the group along its short path is left to
// the next round of (3.1)-(3.2), as for the group's largest cluster: an overlap it leaves
// there is a new contact of that round. Its spheres are still checked against every other
// cluster of the group. In a large run many retreating spheres are in such clusters, and
// searching their paths outside the group would cost more than the rounds it spares.
inline constexpr int kOutsideSearchedClusterSize = 64;

// Whether the fall-backs search the paths of cluster c's spheres for spheres outside the group.
template <int D>
bool searched_against_outside(const State<D>& s, int c) {
  return s.clusters[c].size() <= kOutsideSearchedClusterSize;
}

// The distance from the origin to the segment from p to p + d.
template <int D>
inline double distance_to_segment(const Vec<D>& p, const Vec<D>& d) {
  return std::sqrt(squared_distance_to_segment<D>(Vec<D>::Zero(), p, d));
}

// Where a cluster of the group starts its retreat: the bounding sphere of its spheres'
// centres (free flight's end, this step's minimisations undone).
template <int D>
struct RetreatStart {
  Vec<D> centre;
  double radius;
  double longest_shift;  // of its spheres by this step's minimisations
};

template <int D>
std::vector<RetreatStart<D>> retreat_starts(const StepView<D>& ctx,
                                            const std::vector<std::pair<std::int32_t, std::int32_t>>& clusters) {
  const State<D>& s = ctx.state;
  std::vector<RetreatStart<D>> out;
  for (const auto& [c, b] : clusters) {
    const auto& members = s.clusters[c].members;
    auto start = [&](int i) { return Vec<D>(ctx.positions[i] - ctx.step_shift[i]); };
    const Vec<D> first = start(members.front());
    Vec<D> sum = Vec<D>::Zero();  // of the separations from the first sphere (periodic images)
    // A giant's members are scattered over the arrays: their entries are asked for ahead.
    for_each_prefetched(
        members, [&](int i) { sum += s.box.separation(start(i), first); }, ctx.positions, ctx.step_shift);
    const Vec<D> centre = first + sum / static_cast<double>(members.size());
    double radius = 0.0, longest_shift = 0.0;
    for_each_prefetched(
        members,
        [&](int i) {
          radius = std::max(radius, s.box.separation(start(i), centre).norm());
          longest_shift = std::max(longest_shift, ctx.step_shift[i].norm());
        },
        ctx.positions, ctx.step_shift);
    out.push_back({centre, radius, longest_shift});
  }
  return out;
}

template <int D>
struct Retreat {
  double theta;                // the fraction of the flight undone
  bool free;                   // at theta nothing overlaps (false: theta = 1, spheres from outside in the way)
  GroupSolution<D> solution;   // the group moved back by theta, its pairs left touching as contacts
  // With with_candidates, when the retreat is free: every pair that can come within a
  // contact distance along the flights (with a sphere outside the group: where it is now),
  // in no particular order. What the flight sweep starts from; the plain retreat does not
  // need them, nor does the sweep when no instant is free (the searches then stop early).
  std::vector<SpherePair> candidates;
};

template <int D>
Retreat<D> retreat_group(const StepView<D>& ctx, const CollisionGroup& group, bool with_candidates = false);

template <int D>
GroupSolution<D> place_at_contact(const StepView<D>& ctx, const CollisionGroup& group) {
  return retreat_group(ctx, group).solution;
}

extern template Retreat<2> retreat_group<2>(const StepView<2>&, const CollisionGroup&, bool);
extern template Retreat<3> retreat_group<3>(const StepView<3>&, const CollisionGroup&, bool);

}  // namespace ballagg
