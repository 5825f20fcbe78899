#include "ballagg/engines/time_stepping/minimisation_problem.hpp"

#include <algorithm>
#include <limits>
#include <unordered_map>

#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {
namespace {

// Almost-rigid: pairs up to (1 + kRangeMargin) Delta_W apart enter the problem, so that a
// pair drawn into range by the minimisation feels the attraction from then on (a quarter
// of the range: about how far a minimisation draws spheres together).
constexpr double kRangeMargin = 0.25;
// Non-rigid: pairs closer than (2 + kContactMargin) R_max are constrained from the start,
// so that spheres a minimisation brings together do not pass through each other.
constexpr double kContactMargin = 0.5;

std::uint64_t key(int i, int j) {
  if (i > j) std::swap(i, j);
  return (static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j);
}

template <int D>
DahaPair<D> make_pair(const StepView<D>& ctx, int i, int j, int a, int b, double lambda) {
  const State<D>& s = ctx.state;
  DahaPair<D> q;
  q.a = a;
  q.b = b;
  q.base = s.box.separation(ctx.positions[i], ctx.positions[j]) / ctx.length_scale;
  q.sigma = (s.spheres.radius[i] + s.spheres.radius[j]) / ctx.length_scale;
  q.lambda = lambda;
  return q;
}

template <int D>
double largest_stretch(const DahaProblem<D>& prob, const std::vector<Vec<D>>& u, std::size_t first, std::size_t last) {
  double stretch = -1.0;
  for (std::size_t p = first; p < last; ++p) {
    const DahaPair<D>& q = prob.pairs[p];
    stretch = std::max(stretch, (q.base + u[q.a] - u[q.b]).norm() / q.sigma - 1.0);
  }
  return stretch;
}

// Guards reach neighbours whose gap is below this fraction of the largest diameter: about
// the farthest a guarded sphere moves in one minimisation.
constexpr double kGuardGap = 1.0;

// Guards: every pair of a sphere of a small cluster of the group and a sphere of another
// body closer than kGuardGap diameters, not in S. Inside the group the pair is constrained
// between two variables; with a sphere outside, that sphere is held where it is (the
// variable `fixed`, which never moves). Without guards a minimisation pushes spheres
// blindly into their neighbours, and every round of (3.1)-(3.2) finds new contacts; with
// them it looks for a configuration that is free of overlaps all around (the direction of
// the paper's Remark 3.2). Spheres of larger clusters are not guarded (they move little;
// see for_each_neighbour_of_group).
template <int D>
void add_guards(const StepView<D>& ctx, const CollisionGroup& g, int fixed, DahaProblem<D>& prob,
                std::vector<SpherePair>& sphere_pairs) {
  const State<D>& s = ctx.state;
  const double gap = kGuardGap * 2.0 * s.max_radius();
  const std::size_t first = prob.pairs.size();
  // The pairs of S already in the problem (those of the group: a pair of S joins two bodies
  // of one group), sorted, to leave them out: asking S itself would be a hash lookup per
  // neighbour, most of them cache misses while S is large.
  std::vector<std::uint64_t> in_s;
  for (std::size_t k = 0; k < first; ++k) in_s.push_back(key(sphere_pairs[k].i, sphere_pairs[k].j));
  std::sort(in_s.begin(), in_s.end());
  for_each_neighbour_of_group(ctx, g, 2.0 * s.max_radius() + gap, kSmallClusterSize, [&](int i, int j, int bj) {
    const int bi = body_index(ctx, g, i);
    if (bi == bj) return;  // one body: rigidly linked
    if (bj >= 0 && std::binary_search(in_s.begin(), in_s.end(), key(i, j))) return;  // in S
    const double sigma = s.spheres.radius[i] + s.spheres.radius[j];
    if (s.box.separation(ctx.positions[i], ctx.positions[j]).norm() > sigma + gap) return;
    DahaPair<D> q = make_pair(ctx, i, j, bi, bj >= 0 ? bj : fixed, 0.0);
    q.attract = false;
    q.guard = true;
    prob.pairs.push_back(q);
    sphere_pairs.push_back({std::min(i, j), std::max(i, j), 0.0});
  });
  // In pair order, not in the order the cell list happened to visit them (the sums of the
  // minimisation would otherwise depend on how spheres were binned).
  std::vector<std::size_t> order(prob.pairs.size() - first);
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = first + k;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return pair_less(sphere_pairs[a], sphere_pairs[b]); });
  std::vector<DahaPair<D>> guards;
  std::vector<SpherePair> guarded;
  for (std::size_t k : order) {
    guards.push_back(prob.pairs[k]);
    guarded.push_back(sphere_pairs[k]);
  }
  std::copy(guards.begin(), guards.end(), prob.pairs.begin() + first);
  std::copy(guarded.begin(), guarded.end(), sphere_pairs.begin() + first);
}

// The walls as bounds on the displacements (DahaProblem::lower/upper), from each variable's
// bounding box [lo, hi] (radii included, unscaled): it may move towards a wall until it
// touches it, and not at all into a wall it already pokes through (the next step moves it
// back). A variable wider than the box along an axis is left free along it.
template <int D>
void bound_by_walls(const StepView<D>& ctx, const std::vector<Vec<D>>& lo, const std::vector<Vec<D>>& hi,
                    DahaProblem<D>& prob) {
  const Box<D>& box = ctx.state.box;
  if (box.periodic()) return;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const std::size_t n = prob.inverse_mass.size();
  prob.lower.assign(n, Vec<D>::Constant(-inf));
  prob.upper.assign(n, Vec<D>::Constant(inf));
  for (std::size_t k = 0; k < lo.size(); ++k)
    for (int a = 0; a < D; ++a) {
      if (!(lo[k][a] <= hi[k][a]) || hi[k][a] - lo[k][a] > box.length) continue;  // no spheres, or too wide
      prob.lower[k][a] = std::min(0.0, -lo[k][a]) / ctx.length_scale;
      prob.upper[k][a] = std::max(0.0, box.length - hi[k][a]) / ctx.length_scale;
    }
}

// The pairs that touch (|d / sigma - 1| <= eps_c) at the solution u.
template <int D>
std::vector<SpherePair> touching_pairs(const DahaProblem<D>& prob, const std::vector<SpherePair>& sphere_pairs,
                                       const std::vector<Vec<D>>& u, double eps_c) {
  std::vector<SpherePair> out;
  for (std::size_t k = 0; k < prob.pairs.size(); ++k) {
    const DahaPair<D>& q = prob.pairs[k];
    if (std::abs((q.base + u[q.a] - u[q.b]).norm() / q.sigma - 1.0) <= eps_c)
      out.push_back({sphere_pairs[k].i, sphere_pairs[k].j, q.lambda});
  }
  return out;
}

// Rigid model: one variable per body, of the body's mass.
template <int D>
GroupSolution<D> solve_rigid(const StepView<D>& ctx, const CollisionGroup& g) {
  const State<D>& s = ctx.state;
  const auto clusters = clusters_of_group(ctx, g);
  DahaProblem<D> prob;
  std::vector<double> mass(g.bodies.size(), 0.0);
  for (const auto& [c, b] : clusters) mass[b] += s.clusters[c].mass;
  for (double m : mass) prob.inverse_mass.push_back(ctx.mean_mass / m);
  const int fixed = static_cast<int>(prob.inverse_mass.size());
  prob.inverse_mass.push_back(0.0);
  std::vector<SpherePair> sphere_pairs;
  std::vector<int> touching;
  for (int idx : g.pairs) {
    const SpherePair& p = ctx.S.pairs()[idx];
    prob.pairs.push_back(make_pair(ctx, p.i, p.j, body_index(ctx, g, p.i), body_index(ctx, g, p.j), p.lambda));
    sphere_pairs.push_back(p);
    touching.push_back(p.i);
    touching.push_back(p.j);
  }
  std::sort(touching.begin(), touching.end());
  prob.n_spheres = static_cast<int>(std::unique(touching.begin(), touching.end()) - touching.begin());
  add_guards(ctx, g, fixed, prob, sphere_pairs);
  if (!s.box.periodic()) {
    // Each body's bounding box from its clusters' (O(1) per cluster): every sphere of a
    // cluster has the same step shift in this model.
    constexpr double inf = std::numeric_limits<double>::infinity();
    std::vector<Vec<D>> lo(g.bodies.size(), Vec<D>::Constant(inf)), hi(g.bodies.size(), Vec<D>::Constant(-inf));
    for (const auto& [c, b] : clusters) {
      const Vec<D> at = s.origin(c, s.time) + ctx.step_shift[s.clusters[c].members.front()];
      lo[b] = lo[b].cwiseMin(at + s.extent(c).lo);
      hi[b] = hi[b].cwiseMax(at + s.extent(c).hi);
    }
    bound_by_walls(ctx, lo, hi, prob);
  }

  GroupSolution<D> out;
  std::vector<Vec<D>> u;
  if (ctx.sink) ctx.sink->record(prob);
  out.result = minimise(prob, ctx.settings.daha, u, ctx.guard);

  out.n_variables = static_cast<int>(g.bodies.size());
  out.contacts = touching_pairs(prob, sphere_pairs, u, ctx.settings.daha.eps_c);
  for (const auto& [c, b] : clusters) {
    const Vec<D> shift = u[b] * ctx.length_scale;
    if (shift == Vec<D>::Zero()) continue;
    for (int m : s.clusters[c].members) {
      out.spheres.push_back(m);
      out.shift.push_back(shift);
    }
  }
  return out;
}

// Start positions of the group's spheres, unwrapped (one image of the whole group, even
// when it is wider than a periodic box): within a cluster from the sphere offsets plus what
// this step's earlier rounds moved each sphere (the state moves only at the end of the step;
// without the step's shifts the attraction would act on where the spheres were at the
// start of the step and push each sphere a round had moved further the same way at every
// later round, opening its links), and from cluster to cluster across the pairs of S and
// the links that join them.
template <int D>
std::vector<Vec<D>> unwrapped_starts(const StepView<D>& ctx, const CollisionGroup& g,
                                     const std::vector<std::pair<std::int32_t, std::int32_t>>& clusters,
                                     const std::unordered_map<int, int>& local, int n_spheres) {
  const State<D>& s = ctx.state;
  std::vector<Vec<D>> x(n_spheres);
  std::unordered_map<int, int> index_of_cluster;
  for (std::size_t k = 0; k < clusters.size(); ++k) index_of_cluster.emplace(clusters[k].first, static_cast<int>(k));
  std::vector<char> placed(clusters.size(), 0);
  auto place = [&](int k, int known_sphere, const Vec<D>& at) {
    const Vec<D> known = s.spheres.offset[known_sphere] + ctx.step_shift[known_sphere];
    for (int m : s.clusters[clusters[k].first].members)
      x[local.at(m)] = at + (s.spheres.offset[m] + ctx.step_shift[m]) - known;
    placed[k] = 1;
  };
  std::vector<SpherePair> joins;
  for (int idx : g.pairs) joins.push_back(ctx.S.pairs()[idx]);
  for (int body : g.bodies)
    for (const SpherePair& l : ctx.bodies.links_of(body)) joins.push_back(l);
  const int first = s.clusters[clusters[0].first].members.front();
  place(0, first, ctx.positions[first]);
  for (bool progress = true; progress;) {  // a few sweeps: groups are small trees of clusters
    progress = false;
    for (const SpherePair& p : joins) {
      const int a = index_of_cluster.at(s.spheres.cluster[p.i]), b = index_of_cluster.at(s.spheres.cluster[p.j]);
      if (placed[a] == placed[b]) continue;
      const int from = placed[a] ? p.i : p.j, to = placed[a] ? p.j : p.i;
      const Vec<D> hop = s.box.separation(ctx.positions[to], ctx.positions[from]);
      place(placed[a] ? b : a, to, x[local.at(from)] + hop);
      progress = true;
    }
  }
  return x;
}

// Non-rigid and almost-rigid: one variable per sphere of the group. Constraints on S, on
// the old links and on every pair close enough to come into contact; attraction over all
// pairs (non-rigid) or over the pairs within Delta_W (almost-rigid). Built in named steps:
// the group's spheres, their variables, the pairs, then the solution read back.
template <int D>
class PerSphereProblem {
 public:
  PerSphereProblem(const StepView<D>& ctx, const CollisionGroup& g);
  GroupSolution<D> solve();

 private:
  void mark_mobile();
  void assign_variables();
  void add(int i, int j, double lambda, bool bond = false);
  void add_pairs();
  std::vector<SpherePair> links_of_the_solution(const std::vector<Vec<D>>& u) const;

  const StepView<D>& ctx_;
  const State<D>& s_;
  const CollisionGroup& g_;
  const bool local_attraction_;   // almost-rigid
  const bool paper_;              // ts.method = "paper": every sphere mobile, no bond cap, rectangles of side Delta_W
  std::vector<int> spheres_;      // of the group, cluster by cluster
  std::vector<Vec<D>> x_;         // their positions
  std::unordered_map<int, int> local_;  // sphere -> index in spheres_
  double reach_;                  // pairs closer than this enter the problem
  SortedCellList<D> cells_;       // over x_, cells of side reach_
  std::vector<char> mobile_;      // per sphere: a variable of its own
  std::vector<int> variable_;     // of each sphere of the group
  std::vector<double> mass_;      // of each variable
  DahaProblem<D> prob_;
  std::unordered_map<std::uint64_t, int> index_;  // pair key -> position in prob_.pairs
  std::vector<SpherePair> sphere_pairs_;          // of each pair of the problem
  std::vector<SpherePair> links_;                 // the old links, for their new multipliers
  std::size_t first_link_ = 0, last_link_ = 0;    // the links' range in prob_.pairs
};

// The spheres of the group's clusters, cluster by cluster.
template <int D>
std::vector<int> spheres_of_group(const StepView<D>& ctx, const CollisionGroup& g) {
  std::vector<int> spheres;
  for (const auto& [c, b] : clusters_of_group(ctx, g))
    spheres.insert(spheres.end(), ctx.state.clusters[c].members.begin(), ctx.state.clusters[c].members.end());
  return spheres;
}

template <int D>
std::vector<Vec<D>> positions_of(const StepView<D>& ctx, const std::vector<int>& spheres) {
  std::vector<Vec<D>> x;
  for (int i : spheres) x.push_back(ctx.positions[i]);
  return x;
}

template <int D>
PerSphereProblem<D>::PerSphereProblem(const StepView<D>& ctx, const CollisionGroup& g)
    : ctx_(ctx),
      s_(ctx.state),
      g_(g),
      local_attraction_(ctx.settings.model == TsModel::almost_rigid),
      paper_(ctx.settings.method == TsMethod::paper),
      spheres_(spheres_of_group(ctx, g)),
      x_(positions_of(ctx, spheres_)),
      reach_(!local_attraction_ ? (2.0 + kContactMargin) * s_.max_radius()
             : paper_           ? ctx.delta_w
                                : (1.0 + kRangeMargin) * ctx.delta_w),
      cells_(s_.box, reach_, static_cast<int>(x_.size())) {
  local_.reserve(spheres_.size());
  for (std::size_t a = 0; a < spheres_.size(); ++a) local_.emplace(spheres_[a], static_cast<int>(a));
  prob_.n_spheres = static_cast<int>(spheres_.size());
  prob_.range = ctx.delta_w / ctx.length_scale;
  if (!local_attraction_) {
    for (const Vec<D>& x : unwrapped_starts(ctx, g, clusters_of_group(ctx, g), local_, static_cast<int>(spheres_.size())))
      prob_.position.push_back(x / ctx.length_scale);
  }
  cells_.build(x_);
  mark_mobile();
  assign_variables();
  add_pairs();
  if (paper_)
    for (const Vec<D>& x : x_) prob_.start.push_back(x / ctx.length_scale);  // every sphere is a variable
}

// Almost-rigid: cells of side Delta_W (the "rectangles" of §3.3) over the group's spheres
// find the pairs within range. The spheres within Delta_W of a sphere of a new contact
// move each on its own; the rest of each cluster moves as one rigid part (one variable of
// its mass), so a cluster deforms only near the impact ("a partial rigid body, where some
// elasticity is admitted but only locally") and is carried as a whole by its links
// otherwise. Non-rigid, and the paper's method (§3.3 moves every sphere): every sphere is
// mobile.
template <int D>
void PerSphereProblem<D>::mark_mobile() {
  mobile_.assign(spheres_.size(), local_attraction_ && !paper_ ? 0 : 1);
  if (!local_attraction_ || paper_) return;
  for (int idx : g_.pairs)
    for (int i : {ctx_.S.pairs()[idx].i, ctx_.S.pairs()[idx].j}) {
      const Vec<D>& xi = x_[local_.at(i)];
      cells_.for_each_near(xi, [&](int b) {
        if (s_.box.separation(xi, x_[b]).norm() <= reach_) mobile_[b] = 1;
      });
    }
}

// A variable per mobile sphere and per rigid part, with its mass and, between walls, the
// box of displacements that keeps its spheres inside.
template <int D>
void PerSphereProblem<D>::assign_variables() {
  variable_.resize(spheres_.size());
  std::unordered_map<int, int> rigid_part;  // cluster -> variable of its rigid part
  for (std::size_t a = 0; a < spheres_.size(); ++a) {
    const double m = s_.spheres.mass[spheres_[a]];
    if (mobile_[a]) {
      variable_[a] = static_cast<int>(mass_.size());
      mass_.push_back(m);
      continue;
    }
    const auto [it, added] = rigid_part.emplace(s_.spheres.cluster[spheres_[a]], static_cast<int>(mass_.size()));
    if (added) mass_.push_back(0.0);
    variable_[a] = it->second;
    mass_[it->second] += m;
  }
  for (double m : mass_) prob_.inverse_mass.push_back(ctx_.mean_mass / m);
  if (s_.box.periodic()) return;
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<Vec<D>> lo(mass_.size(), Vec<D>::Constant(inf)), hi(mass_.size(), Vec<D>::Constant(-inf));
  for (std::size_t a = 0; a < spheres_.size(); ++a) {
    const double r = s_.spheres.radius[spheres_[a]];
    lo[variable_[a]] = lo[variable_[a]].cwiseMin(x_[a] - Vec<D>::Constant(r));
    hi[variable_[a]] = hi[variable_[a]].cwiseMax(x_[a] + Vec<D>::Constant(r));
  }
  bound_by_walls(ctx_, lo, hi, prob_);
}

// A pair is constrained; in the almost-rigid model it also attracts, while within Delta_W
// (3.30) — a link (an adhesive bond, which this model never breaks) at any distance, and
// may not stretch beyond (1 + bond_stretch) sigma. In the non-rigid model the attraction
// is the all-pairs term. The paper's method: a link is a pair like any other, (3.30)
// attracts it while within Delta_W, and nothing bounds its length.
template <int D>
void PerSphereProblem<D>::add(int i, int j, double lambda, bool bond) {
  const int a = variable_[local_.at(i)], b = variable_[local_.at(j)];
  if (a == b) return;  // within one rigid part (or a sphere with itself)
  if (!index_.emplace(key(i, j), static_cast<int>(prob_.pairs.size())).second) return;
  DahaPair<D> q = make_pair(ctx_, i, j, a, b, lambda);
  q.attract = local_attraction_;
  q.attract_within_range = local_attraction_ && (paper_ || !bond);
  if (local_attraction_ && bond && !paper_) q.stretch_limit = (1.0 + ctx_.settings.bond_stretch) * q.sigma;
  prob_.pairs.push_back(q);
  sphere_pairs_.push_back({std::min(i, j), std::max(i, j), lambda});
}

// S, then the old links and this step's links (the bodies' own, which hold their clusters
// together like old links; their multipliers stay with the bodies), then every pair within
// reach. The paper's method, almost-rigid (3.31): every pair of spheres in the same or
// neighbouring rectangles (cells of side Delta_W), whatever their distance.
template <int D>
void PerSphereProblem<D>::add_pairs() {
  for (int idx : g_.pairs) add(ctx_.S.pairs()[idx].i, ctx_.S.pairs()[idx].j, ctx_.S.pairs()[idx].lambda);
  first_link_ = prob_.pairs.size();
  for (int i : spheres_)
    for (const LinkEnd& e : ctx_.links.of(i)) {
      if (variable_[local_.at(i)] == variable_[local_.at(e.other)]) continue;
      links_.push_back({i, e.other, e.lambda});
      add(i, e.other, e.lambda, true);
    }
  for (int body : g_.bodies)
    for (const SpherePair& l : ctx_.bodies.links_of(body)) add(l.i, l.j, l.lambda, true);
  last_link_ = prob_.pairs.size();
  for (std::size_t a = 0; a < x_.size(); ++a)
    cells_.for_each_near(x_[a], [&](int b) {
      if (b > static_cast<int>(a) &&
          ((paper_ && local_attraction_) || s_.box.separation(x_[a], x_[b]).squaredNorm() <= reach_ * reach_))
        add(spheres_[a], spheres_[b], 0.0);
    });
}

template <int D>
GroupSolution<D> PerSphereProblem<D>::solve() {
  GroupSolution<D> out;
  std::vector<Vec<D>> u;
  if (ctx_.sink) ctx_.sink->record(prob_);
  out.result = minimise(prob_, ctx_.settings.daha, u, ctx_.guard);
  out.n_variables = static_cast<int>(mass_.size());
  // The paper's method links every pair of S (it is S that makes the clusters), so those
  // count among the links whose stretch is reported.
  out.link_stretch = largest_stretch(prob_, u, paper_ ? 0 : first_link_, last_link_);
  for (SpherePair& l : links_) l.lambda = prob_.pairs[index_.at(key(l.i, l.j))].lambda;
  out.old_links = std::move(links_);
  out.contacts = links_of_the_solution(u);
  for (std::size_t a = 0; a < spheres_.size(); ++a) {
    const Vec<D> shift = u[variable_[a]] * ctx_.length_scale;
    if (shift == Vec<D>::Zero()) continue;
    out.spheres.push_back(spheres_[a]);
    out.shift.push_back(shift);
  }
  return out;
}

// The new links a solution makes. Ours: the pairs it leaves touching, within eps_c (a
// converged solution leaves every pair of S touching or apart). The paper's method, (3.2):
// every pair of S, converged or not, and every other pair left touching or overlapping
// (1 - d / sigma >= -eps_c: phi >= 0 up to the contact tolerance).
template <int D>
std::vector<SpherePair> PerSphereProblem<D>::links_of_the_solution(const std::vector<Vec<D>>& u) const {
  const double eps_c = ctx_.settings.daha.eps_c;
  std::vector<SpherePair> out;
  for (std::size_t k = 0; k < prob_.pairs.size(); ++k) {
    if (k >= first_link_ && k < last_link_) continue;  // a link already
    const DahaPair<D>& q = prob_.pairs[k];
    const double gap = 1.0 - (q.base + u[q.a] - u[q.b]).norm() / q.sigma;
    const bool in_s = k < first_link_;
    if (paper_ ? (in_s || gap >= -eps_c) : std::abs(gap) <= eps_c)
      out.push_back({sphere_pairs_[k].i, sphere_pairs_[k].j, q.lambda});
  }
  return out;
}

template <int D>
GroupSolution<D> solve_per_sphere(const StepView<D>& ctx, const CollisionGroup& g) {
  PerSphereProblem<D> problem(ctx, g);
  return problem.solve();
}

}  // namespace

template <int D>
GroupSolution<D> solve_group(const StepView<D>& ctx, const CollisionGroup& group) {
  if (ctx.settings.model == TsModel::rigid) return solve_rigid(ctx, group);
  return solve_per_sphere(ctx, group);
}

template GroupSolution<2> solve_group<2>(const StepView<2>&, const CollisionGroup&);
template GroupSolution<3> solve_group<3>(const StepView<3>&, const CollisionGroup&);

}  // namespace ballagg
