// What the time-stepping engine (ts_engine.hpp) does when the loop (3.1)-(3.2) gives up
// with pairs still overlapping: the clusters of the deeper ones retreat together along
// their flights until nothing is left overlapping, and the pairs left touching are links.
#include <algorithm>

#include "ballagg/engines/time_stepping/retreat.hpp"
#include "ballagg/engines/time_stepping/ts_engine.hpp"

namespace ballagg {

// When the loop gives up (out of rounds, a repeating round, a round that changes nothing)
// with pairs still overlapping: pairs touching within eps_c become links; the clusters of
// the deeper ones, and every cluster linked to them in this step, retreat together along
// their flights (place_at_contact of one group), and the spheres that retreat finds in
// their way join the group and the retreat is made again, until it leaves no overlap
// beyond eps_c. It ends: the group only grows, and a group of every cluster that moved in
// the step returns to the start of the step, where no two clusters overlapped. The pairs
// it leaves touching are links, so the clusters merge and the run goes on.
//
// A step that must end (RunGuard::step_must_end: the wall-clock limit, or a signal that has
// waited) ends its settling at once with that last resort: every cluster back where it
// was at the start of the step (return_to_start). A settling of a very long step can go
// on for many minutes (docs/time_stepping.md, "When the loop gives up").
//
// Left apart, such an overlap would outlive the step: neither a minimisation nor a retreat
// (which goes back at most to the start of the step) could separate it at a later step,
// and the run would stop making progress. Merged where they are, deep overlaps would be
// frozen into the aggregates.
template <int D>
void TimeSteppingEngine<D>::settle(const State<D>& s, const std::vector<SpherePair>& left) {
  const double eps_c = settings_.daha.eps_c;
  auto deep = [&](const SpherePair& p) {
    const double sigma = s.spheres.radius[p.i] + s.spheres.radius[p.j];
    return 1.0 - s.box.separation(positions_[p.i], positions_[p.j]).norm() / sigma > eps_c;
  };
  std::vector<std::int32_t> retreating;  // clusters, sorted
  for (const SpherePair& p : left)
    if (deep(p))
      for (int i : {p.i, p.j}) retreating.push_back(s.spheres.cluster[i]);
  sort_unique(retreating);
  std::vector<std::int32_t> group_clusters;  // sorted
  std::vector<int> settled;                  // spheres moved by the retreats
  std::vector<SpherePair> contacts;
  while (!retreating.empty()) {
    if (guard_ != nullptr && guard_->step_must_end()) {
      return_to_start(s);
      return;
    }
    // Every cluster linked to a retreating one in this step retreats with it: where their
    // flights started, they were free of each other.
    for (int c : retreating) {
      const int body = bodies_.body_of(c);
      for (int k : bodies_.clusters_of(body)) group_clusters.push_back(k);
      bodies_.dissolve(body);
    }
    sort_unique(group_clusters);
    const GroupSolution<D> solution = place_at_contact(view(s), CollisionGroup{group_clusters, {}});
    std::vector<int> moved(solution.spheres.begin(), solution.spheres.end());
    apply(s, solution, settled);
    contacts = solution.contacts;
    // Only what moved now can overlap anything new: nothing outside the group moves here.
    retreating = clusters_overlapping_outside(s, moved, group_clusters);
  }
  moved_in_step_.insert(moved_in_step_.end(), settled.begin(), settled.end());
  for (const SpherePair& p : contacts) bodies_.link(p, s.spheres.cluster[p.i], s.spheres.cluster[p.j]);
  // The pairs that were only touching are links, unless one of their clusters retreated.
  auto retreated = [&](int i) {
    return std::binary_search(group_clusters.begin(), group_clusters.end(), s.spheres.cluster[i]);
  };
  for (const SpherePair& p : left)
    if (!deep(p) && !retreated(p.i) && !retreated(p.j))
      bodies_.link(p, s.spheres.cluster[p.i], s.spheres.cluster[p.j]);
}

// Every cluster back where it was at the start of the step, where no two clusters
// overlapped, and every body of the step dissolved: the step merges nothing, its clusters
// stood still for it.
template <int D>
void TimeSteppingEngine<D>::return_to_start(const State<D>& s) {
  GroupSolution<D> back;
  back.placed_at_contact = true;
  back.dissolves_bodies = true;
  back.result.converged = true;
  for (int c : s.alive_clusters()) {
    bodies_.dissolve(bodies_.body_of(c));
    for (int i : s.clusters[c].members) {
      const Vec<D> shift = -step_shift_[i] - flight_[c];
      if (shift == Vec<D>::Zero()) continue;
      back.spheres.push_back(i);
      back.shift.push_back(shift);
    }
  }
  std::vector<int> moved;
  apply(s, back, moved);
  moved_in_step_.insert(moved_in_step_.end(), moved.begin(), moved.end());
}

template void TimeSteppingEngine<2>::settle(const State<2>&, const std::vector<SpherePair>&);
template void TimeSteppingEngine<3>::settle(const State<3>&, const std::vector<SpherePair>&);
template void TimeSteppingEngine<2>::return_to_start(const State<2>&);
template void TimeSteppingEngine<3>::return_to_start(const State<3>&);

}  // namespace ballagg
