#include "ballagg/engines/time_stepping/flight_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>
#include <utility>
#include <vector>

#include "ballagg/collision/crossing.hpp"
#include "ballagg/core/disjoint_sets.hpp"
#include "ballagg/core/prefetch.hpp"

namespace ballagg {
namespace {

constexpr double kNoContact = std::numeric_limits<double>::infinity();

// A body whose clusters hold at least this many spheres that are searched from (not the
// group's giant) is searched on several threads: the sweep of a group holding a large
// body often runs alone, with a search after each of the body's events, and a search of a
// few thousand spheres outweighs starting the threads.
constexpr std::size_t kParallelSearchSpheres = 2048;

// How many spheres of one cluster make one task of a parallel search's outside searches:
// small enough to share a large cluster among the threads, large enough to outweigh a task.
constexpr std::size_t kOutsideSearchPiece = 256;

// The first t >= 0 at which |B + t V| = sigma while the pair closes in (kNoContact: never).
// A pair already within sigma and closing in touches at once; one moving apart never.
template <int D>
double first_contact(const Vec<D>& B, const Vec<D>& V, double sigma) {
  const double b = B.dot(V);
  if (b >= 0.0) return kNoContact;  // not closing in: the distance only grows from here
  const crossing::Quadratic q{V.squaredNorm(), b, B.squaredNorm() - sigma * sigma};
  if (q.c <= 0.0) return 0.0;
  const double disc = crossing::discriminant(q);
  if (disc < 0.0) return kNoContact;
  return crossing::entry(q, std::sqrt(disc));
}

// The sweep of one group, tau in [0, 1] the fraction of the step from its start. Cluster k
// of the group (clusters_[k]) has its spheres at e_i + a_k + tau v_k, where e_i is the end
// of sphere i's free flight (its position with this step's minimisations undone): a_k =
// -flight, v_k = flight until its body changes.
template <int D>
class FlightSweep {
 public:
  FlightSweep(const StepView<D>& ctx, const CollisionGroup& g)
      : ctx_(ctx),
        s_(ctx.state),
        queried_(ctx, g, std::numeric_limits<int>::max()),
        clusters_(queried_.clusters),
        starts_(retreat_starts(ctx, clusters_)),
        contact_reach_(2.0 * s_.max_radius() * (1.0 + ctx.settings.daha.eps_c)),
        margin_(ctx.settings.sweep_reuse_margin * s_.max_radius()) {
    const std::size_t n = clusters_.size();
    for (std::size_t k = 0; k < n; ++k) index_.push_back({clusters_[k].first, static_cast<std::int32_t>(k)});
    std::sort(index_.begin(), index_.end());
    a_.resize(n);
    v_.resize(n);
    epoch_.assign(n, 0);
    bodies_ = DisjointSets(static_cast<int>(n));
    members_.resize(n);
    frozen_.assign(n, 0);
    outside_kept_.resize(n);  // per cluster, its pieces when it is first searched
    for (std::size_t k = 0; k < n; ++k) {
      v_[k] = ctx.flight[clusters_[k].first];
      a_[k] = -v_[k];
      members_[k] = {static_cast<int>(k)};
    }
  }

  GroupSolution<D> run(Retreat<D> retreat);

 private:
  struct Event {
    double tau;
    int i, j;   // the spheres (i = -1: k's body reaches a wall)
    int k, m;   // their clusters in the group (m = -1: j is outside it)
    int ek, em; // the epochs of k and m when the event was found
    bool operator>(const Event& o) const {
      if (tau != o.tau) return tau > o.tau;
      if (i != o.i) return i > o.i;
      if (j != o.j) return j > o.j;
      if (k != o.k) return k > o.k;
      return m > o.m;
    }
  };

  int local(int cluster) const {
    const auto it = std::lower_bound(index_.begin(), index_.end(), std::pair<std::int32_t, std::int32_t>{cluster, -1});
    return it != index_.end() && it->first == cluster ? it->second : -1;
  }
  int root(int k) { return bodies_.find(k); }
  Vec<D> end_of_flight(int i) const { return ctx_.positions[i] - ctx_.step_shift[i]; }
  Vec<D> displacement(int k, double tau) const { return a_[k] + tau * v_[k]; }
  const MemberList& spheres(int k) const { return s_.clusters[clusters_[k].first].members; }

  using PairList = std::vector<std::pair<int, int>>;
  // The flight a search looked along, relative to what it searched (displacement a + tau v,
  // from the tau of the search to 1), and the pairs it met within margin_ of a contact.
  struct KeptSearch {
    bool searched = false;
    Vec<D> a, v;
    PairList pairs;
  };
  // A search's task: the pairs of clusters k and m (m >= 0), or those of k's spheres
  // [begin, end) with the spheres outside the group (m = -1). reuse: kept's pairs are all
  // it can meet (run_task tries them); otherwise it searches the cell list and fills kept.
  struct SearchTask {
    int k, m;
    std::size_t begin, end;
    KeptSearch* kept;
    bool reuse;
  };

  void try_pair(int i, int j, int k, int m, double tau, std::vector<Event>& found) const;
  bool can_meet(int k, int m, double tau) const;
  void search_clusters(const SearchTask& task, double tau, std::vector<Event>& found) const;
  void search_outside(const SearchTask& task, double tau, std::vector<Event>& found) const;
  void add_task(int k, int m, std::size_t begin, std::size_t end, KeptSearch& kept, double tau);
  void search_walls(int body, double tau);
  void search(int body, double tau);
  void run_task(const SearchTask& task, double tau, std::vector<Event>& found) const;
  void run_tasks_in_parallel(double tau);
  std::size_t searched_spheres(int body) const;
  void push_found();
  void set_velocity(int body, const Vec<D>& v, double tau);
  int merge(int k, int m, double tau);
  void stop(int k, double tau);
  bool valid(const Event& e);

  const StepView<D>& ctx_;
  const State<D>& s_;
  const QueriedClusters<D> queried_;
  const std::vector<std::pair<std::int32_t, std::int32_t>>& clusters_;  // (cluster, body) of the group
  const std::vector<RetreatStart<D>> starts_;                          // bounding spheres at e
  const double contact_reach_;
  std::vector<std::pair<std::int32_t, std::int32_t>> index_;           // (cluster, k), sorted
  std::vector<Vec<D>> a_, v_;
  std::vector<int> epoch_;              // per cluster: bumped when its motion changes
  DisjointSets bodies_;                 // the bodies of the sweep, sets of clusters (k)
  std::vector<std::vector<int>> members_;  // per root: its clusters
  std::vector<char> frozen_;            // per root: stopped against a sphere outside or a wall
  std::priority_queue<Event, std::vector<Event>, std::greater<Event>> events_;
  std::vector<Event> found_;             // events found by the search under way
  std::vector<SearchTask> tasks_;        // the tasks of the search under way
  std::vector<SpherePair> contacts_;
  // The last search of each piece of kOutsideSearchPiece spheres of a cluster against the
  // spheres outside the group, and of each (searched, other) pair of clusters of the group.
  std::vector<std::vector<KeptSearch>> outside_kept_;
  std::unordered_map<std::int64_t, KeptSearch> pair_kept_;
  // The searches look this much wider than a contact (ts.sweep_reuse_margin radii) and keep
  // the pairs they meet: while the flight searched along (a cluster's, relative to the
  // spheres outside the group or to another cluster of it) stays within margin_ of it, it
  // is searched again from the pairs kept instead of from the cell list. After each event a
  // body's clusters are searched again, and a body that absorbs small clusters one by one
  // changes its flight a little each time: most searches are then of a cluster searched
  // before in the same sweep, on a flight close to the one searched.
  const double margin_;
};

// Sphere i of cluster k and sphere j of cluster m (m = -1: outside the group, where it is
// now), looked at from tau on.
template <int D>
void FlightSweep<D>::try_pair(int i, int j, int k, int m, double tau, std::vector<Event>& found) const {
  const Vec<D> pi = end_of_flight(i) + displacement(k, tau);
  const Vec<D> pj = m >= 0 ? Vec<D>(end_of_flight(j) + displacement(m, tau)) : ctx_.positions[j];
  const Vec<D> relative_velocity = m >= 0 ? Vec<D>(v_[k] - v_[m]) : v_[k];
  const double t = first_contact<D>(s_.box.separation(pi, pj), relative_velocity,
                                    s_.spheres.radius[i] + s_.spheres.radius[j]);
  if (tau + t > 1.0) return;
  found.push_back({tau + t, std::min(i, j), std::max(i, j), k, m, epoch_[k], m >= 0 ? epoch_[m] : 0});
}

// Whether the bounding spheres of clusters k and m come within a contact distance after tau.
template <int D>
bool FlightSweep<D>::can_meet(int k, int m, double tau) const {
  const Vec<D> between = s_.box.separation(Vec<D>(starts_[k].centre + displacement(k, tau)),
                                           Vec<D>(starts_[m].centre + displacement(m, tau)));
  const Vec<D> relative = (1.0 - tau) * (v_[k] - v_[m]);
  return distance_to_segment<D>(between, relative) <= starts_[k].radius + starts_[m].radius + contact_reach_;
}

// The pairs of clusters k and m of the group that can touch after tau (their bounding
// spheres can: can_meet), searched from the side of k, a queried cluster (search() puts
// it first).
template <int D>
void FlightSweep<D>::search_clusters(const SearchTask& task, double tau, std::vector<Event>& found) const {
  const int k = task.k, m = task.m;
  PairList& kept = task.kept->pairs;  // empty: add_task started it afresh
  auto keep = [&](int i, int j) {
    kept.push_back({i, j});
    try_pair(i, j, k, m, tau, found);
  };
  const int other = clusters_[m].first;
  const Vec<D> relative = (1.0 - tau) * (v_[k] - v_[m]);
  const Vec<D> frame = displacement(k, tau) - displacement(m, tau);  // k's motion seen from m's spheres at e
  const double reach = contact_reach_ + margin_;
  for (int i : spheres(k)) {
    const Vec<D> p = end_of_flight(i) + frame;
    if (distance_to_segment<D>(s_.box.separation(p, starts_[m].centre), relative) > starts_[m].radius + reach)
      continue;
    if (s_.clusters[other].size() <= kListedClusterSize) {
      for (int j : s_.clusters[other].members) keep(i, j);
      continue;
    }
    // The cell list holds m's spheres where the step's minimisations put them, up to its
    // longest shift from e.
    ctx_.cells.for_each_near_segment(s_.box.wrap(p), relative, reach + starts_[m].longest_shift + ctx_.cell_slack,
                                     [&](int j) {
                                       if (s_.spheres.cluster[j] == other) keep(i, j);
                                     });
  }
}

// The spheres outside the group that spheres [begin, end) of cluster k can touch after tau.
// For a queried cluster that moves (search() makes no such task for a still one, nor for
// the group's giant or a cluster of more than kOutsideSearchedClusterSize spheres, as in
// the retreat: what they meet is found by the next round).
template <int D>
void FlightSweep<D>::search_outside(const SearchTask& task, double tau, std::vector<Event>& found) const {
  const int k = task.k;
  PairList& kept = task.kept->pairs;  // empty: add_task started it afresh
  const Vec<D> path = (1.0 - tau) * v_[k];
  const MemberList& members = spheres(k);
  for (std::size_t at = task.begin; at < task.end; ++at) {
    const int i = members[at];
    const Vec<D> p = s_.box.wrap(Vec<D>(end_of_flight(i) + displacement(k, tau)));
    ctx_.cells.for_each_near_segment(p, path, contact_reach_ + margin_ + ctx_.cell_slack, [&](int j) {
      // Most spheres met are k's own: they are told apart before the search among the
      // group's clusters.
      const int cj = s_.spheres.cluster[j];
      if (cj != clusters_[k].first && local(cj) < 0) {
        kept.push_back({i, j});
        try_pair(i, j, k, -1, tau, found);
      }
    });
  }
}

// A task for k's flight relative to m (m = -1: to the still spheres outside the group),
// from tau. It reuses kept's pairs when the flight searched there stays within margin_ of
// this one from tau to 1: every pair that can touch on this flight came within margin_ of
// touching on that one. Both flights are straight in tau and the one searched covers tau
// to 1 (the sweep's tau only grows), so it is enough that they are that close at tau and at 1.
template <int D>
void FlightSweep<D>::add_task(int k, int m, std::size_t begin, std::size_t end, KeptSearch& kept, double tau) {
  const Vec<D> a = m >= 0 ? Vec<D>(a_[k] - a_[m]) : a_[k];
  const Vec<D> v = m >= 0 ? Vec<D>(v_[k] - v_[m]) : v_[k];
  auto apart = [&](double t) { return (Vec<D>(a + t * v) - Vec<D>(kept.a + t * kept.v)).norm(); };
  const bool reuse = kept.searched && apart(tau) <= margin_ && apart(1.0) <= margin_;
  if (!reuse) kept = {true, a, v, {}};
  tasks_.push_back({k, m, begin, end, &kept, reuse});
}

// When a body whose flight changed reaches a wall. (A cluster on its own flight stays
// inside: it moves on the segment between two places inside the box.)
template <int D>
void FlightSweep<D>::search_walls(int body, double tau) {
  if (s_.box.periodic() || frozen_[body]) return;
  const Vec<D>& v = v_[body];
  double first = kNoContact;
  int first_k = body;
  for (int k : members_[body]) {
    // The cluster's bounding box (radii included) where free flight put it, the state's
    // place at the step's time, moved as the sweep has moved it: O(1) per cluster, not
    // per sphere (a giant cluster is often in such a body late in a run).
    const ClusterExtent<D>& extent = s_.extent(clusters_[k].first);
    const Vec<D> at = s_.origin(clusters_[k].first, s_.time) + displacement(k, tau);
    for (int axis = 0; axis < D; ++axis) {
      double t = kNoContact;
      if (v[axis] < 0.0) t = std::max(0.0, (at[axis] + extent.lo[axis]) / -v[axis]);
      if (v[axis] > 0.0) t = std::max(0.0, (s_.box.length - at[axis] - extent.hi[axis]) / v[axis]);
      if (t < first) { first = t; first_k = k; }
    }
  }
  if (tau + first <= 1.0) events_.push({tau + first, -1, -1, first_k, -1, epoch_[first_k], 0});
}

// Every event of a body whose motion changed at tau, found by tasks: a pair of clusters
// whose bounding spheres can meet, or up to kOutsideSearchPiece spheres of a queried,
// moving cluster searched against the spheres outside the group. A large body's tasks are
// shared among the threads.
template <int D>
void FlightSweep<D>::search(int body, double tau) {
  tasks_.clear();
  const std::int64_t n = static_cast<std::int64_t>(clusters_.size());
  for (int k : members_[body]) {
    for (int m = 0; m < static_cast<int>(n); ++m) {
      if (root(m) == body || !can_meet(k, m, tau)) continue;
      // Searched from the side of a queried cluster (not the group's giant: its pairs are
      // found from the others').
      const int from = queried_(clusters_[k].first) ? k : m, to = from == k ? m : k;
      add_task(from, to, 0, 0, pair_kept_[from * n + to], tau);
    }
    const int c = clusters_[k].first;
    if (!queried_(c) || !searched_against_outside(s_, c) || v_[k] == Vec<D>::Zero()) continue;
    if (outside_kept_[k].empty()) outside_kept_[k].resize((spheres(k).size() + kOutsideSearchPiece - 1) / kOutsideSearchPiece);
    for (std::size_t begin = 0; begin < spheres(k).size(); begin += kOutsideSearchPiece)
      add_task(k, -1, begin, std::min(spheres(k).size(), begin + kOutsideSearchPiece),
               outside_kept_[k][begin / kOutsideSearchPiece], tau);
  }
  if (tasks_.size() > 1 && searched_spheres(body) >= kParallelSearchSpheres) {
    run_tasks_in_parallel(tau);
  } else {
    for (const SearchTask& task : tasks_) run_task(task, tau, found_);
  }
  push_found();
  search_walls(body, tau);
}

template <int D>
void FlightSweep<D>::run_task(const SearchTask& task, double tau, std::vector<Event>& found) const {
  if (task.reuse) {
    for (const auto& [i, j] : task.kept->pairs) try_pair(i, j, task.k, task.m, tau, found);
  } else if (task.m >= 0) {
    search_clusters(task, tau, found);
  } else {
    search_outside(task, tau, found);
  }
}

// The spheres of the body's clusters that its searches start from.
template <int D>
std::size_t FlightSweep<D>::searched_spheres(int body) const {
  std::size_t n = 0;
  for (int k : members_[body])
    if (queried_(clusters_[k].first)) n += spheres(k).size();
  return n;
}

// The tasks shared among the threads, each thread finding its events apart. The events
// are the same whichever thread finds them and in whatever order they are queued: the
// queue orders them by (tau, spheres, clusters), and equal keys are the same contact (a
// stale copy of one is skipped), so the sweep's result does not depend on the number of
// threads.
template <int D>
void FlightSweep<D>::run_tasks_in_parallel(double tau) {
  const std::int64_t n_tasks = static_cast<std::int64_t>(tasks_.size());
#pragma omp parallel
  {
    std::vector<Event> found;
#pragma omp for schedule(dynamic, 4) nowait
    for (std::int64_t t = 0; t < n_tasks; ++t) run_task(tasks_[t], tau, found);
#pragma omp critical(flight_sweep_found)
    found_.insert(found_.end(), found.begin(), found.end());
  }
}

template <int D>
void FlightSweep<D>::push_found() {
  for (const Event& e : found_) events_.push(e);
  found_.clear();
}

template <int D>
void FlightSweep<D>::set_velocity(int body, const Vec<D>& v, double tau) {
  for (int k : members_[body]) {
    a_[k] += tau * (v_[k] - v);  // the same place at tau
    v_[k] = v;
    ++epoch_[k];
  }
}

// Joins the bodies of clusters k and m at tau with the mass-weighted flight of rule (2.9)
// (none, when either has stopped). Returns the new body.
template <int D>
int FlightSweep<D>::merge(int k, int m, double tau) {
  const int a = root(k), b = root(m);
  // The larger body, or of two equal ones the lower index, absorbs the other (union by
  // size counts clusters, as members_ does): whichever side the contact was found from,
  // the same body keeps the same order of members (the order of the sum below).
  const int big = bodies_.unite(a, b), small = big == a ? b : a;
  members_[big].insert(members_[big].end(), members_[small].begin(), members_[small].end());
  members_[small].clear();
  frozen_[big] = frozen_[big] || frozen_[small];
  Vec<D> momentum = Vec<D>::Zero();
  double mass = 0.0;
  for (int c : members_[big]) {
    const double mc = s_.clusters[clusters_[c].first].mass;
    momentum += mc * v_[c];
    mass += mc;
  }
  set_velocity(big, frozen_[big] ? Vec<D>(Vec<D>::Zero()) : Vec<D>(momentum / mass), tau);
  return big;
}

// k's body stops at tau (it touched a sphere outside the group, or a wall).
template <int D>
void FlightSweep<D>::stop(int k, double tau) {
  const int body = root(k);
  frozen_[body] = 1;
  set_velocity(body, Vec<D>::Zero(), tau);
}

template <int D>
bool FlightSweep<D>::valid(const Event& e) {
  if (epoch_[e.k] != e.ek) return false;
  return e.m < 0 || (epoch_[e.m] == e.em && root(e.k) != root(e.m));
}

template <int D>
GroupSolution<D> FlightSweep<D>::run(Retreat<D> retreat) {
  // The retreat's instant (free, theta > 0: keep_flight sweeps no other): the group
  // overlaps nothing, and its touching pairs join.
  const double start = 1.0 - retreat.theta;
  retreat.solution.release_moves();  // the sweep moves each sphere from the start of the step, not from the retreat
  contacts_ = retreat.solution.contacts;
  std::vector<char> changed(clusters_.size(), 0);
  for (const SpherePair& p : contacts_) {
    const int k = local(s_.spheres.cluster[p.i]), m = local(s_.spheres.cluster[p.j]);
    if (k >= 0 && m >= 0) {
      if (root(k) != root(m)) changed[merge(k, m, start)] = 1;
    } else {
      stop(k >= 0 ? k : m, start);
      changed[root(k >= 0 ? k : m)] = 1;
    }
  }
  // The pairs of clusters still on their own flights are among the retreat's candidates
  // (found along those flights); the bodies that changed at the start are searched again.
  // The order in which events are found does not matter: the queue orders them by (tau,
  // spheres, clusters), and equal keys are the same event.
  for (const SpherePair& p : retreat.candidates) {
    int i = p.i, j = p.j, k = local(s_.spheres.cluster[i]), m = local(s_.spheres.cluster[j]);
    if (k < 0) {
      std::swap(i, j);
      std::swap(k, m);
    }
    if (!changed[root(k)] && (m < 0 || !changed[root(m)])) try_pair(i, j, k, m, start, found_);
  }
  std::vector<SpherePair>().swap(retreat.candidates);  // read only above
  push_found();
  for (int k = 0; k < static_cast<int>(clusters_.size()); ++k)
    if (root(k) == k && changed[k]) search(k, start);
  while (!events_.empty()) {
    const Event e = events_.top();
    events_.pop();
    if (!valid(e)) continue;
    if (e.i >= 0) contacts_.push_back({e.i, e.j, 0.0});
    if (e.m < 0) {
      stop(e.k, e.tau);  // at a sphere outside the group, or at a wall
      search(root(e.k), e.tau);
    } else {
      search(merge(e.k, e.m, e.tau), e.tau);
    }
  }

  GroupSolution<D> out;
  out.placed_at_contact = true;
  out.dissolves_bodies = true;
  out.result = retreat.solution.result;
  out.n_variables = static_cast<int>(clusters_.size());
  std::sort(contacts_.begin(), contacts_.end(), pair_less<SpherePair>);
  contacts_.erase(std::unique(contacts_.begin(), contacts_.end(),
                              [](const SpherePair& x, const SpherePair& y) { return x.i == y.i && x.j == y.j; }),
                  contacts_.end());
  out.contacts = std::move(contacts_);
  for (int k = 0; k < static_cast<int>(clusters_.size()); ++k) {
    auto move_on = [&](int i) {
      const Vec<D> shift = displacement(k, 1.0) - ctx_.step_shift[i];
      if (shift == Vec<D>::Zero()) return;
      out.spheres.push_back(i);
      out.shift.push_back(shift);
    };
    for_each_prefetched(spheres(k), move_on, ctx_.step_shift);
  }
  return out;
}

}  // namespace

template <int D>
GroupSolution<D> keep_flight(const StepView<D>& ctx, const CollisionGroup& group) {
  Retreat<D> retreat = retreat_group(ctx, group, true);
  // Nothing to sweep when the group is back at the start of the step (most retreats of a
  // large run) or where free flight put it: the sweep's set-up (the group's bounding
  // spheres, a pass over every sphere of its clusters) is not made.
  if (!retreat.free || retreat.theta <= 0.0) return std::move(retreat.solution);
  FlightSweep<D> sweep(ctx, group);
  return sweep.run(std::move(retreat));
}

template GroupSolution<2> keep_flight<2>(const StepView<2>&, const CollisionGroup&);
template GroupSolution<3> keep_flight<3>(const StepView<3>&, const CollisionGroup&);

}  // namespace ballagg
