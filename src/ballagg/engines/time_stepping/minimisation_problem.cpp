#include "ballagg/engines/time_stepping/minimisation_problem.hpp"

#include <algorithm>
#include <unordered_map>

#include "ballagg/spatial/sorted_cell_list.hpp"

namespace ballagg {
namespace {

// Almost-rigid: pairs up to (1 + kRangeMargin) Delta_W apart enter the problem, so that a
// pair drawn into range by the minimisation feels the attraction from then on.
constexpr double kRangeMargin = 0.25;
// Non-rigid: pairs closer than (2 + kContactMargin) R_max are constrained from the start.
constexpr double kContactMargin = 0.5;

std::uint64_t key(int i, int j) {
  if (i > j) std::swap(i, j);
  return (static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j);
}

// Where sphere i starts the minimisation (box units, not folded).
template <int D>
Vec<D> start_position(const ProblemContext<D>& ctx, const GroupStart& start, int i) {
  if (!start.backtrack) return ctx.positions[i];
  return ctx.positions[i] - ctx.step_shift[i] - start.retreat * ctx.flight[ctx.state.spheres.cluster[i]];
}

// The displacement from the current centre of sphere i to u (scaled) away from its start.
template <int D>
Vec<D> shift_from_start(const ProblemContext<D>& ctx, const GroupStart& start, int i, const Vec<D>& u) {
  return start_position(ctx, start, i) - ctx.positions[i] + u * ctx.length_scale;
}

template <int D>
DahaPair<D> make_pair(const ProblemContext<D>& ctx, const GroupStart& start, int i, int j, int a, int b, double lambda) {
  const State<D>& s = ctx.state;
  DahaPair<D> q;
  q.a = a;
  q.b = b;
  q.base = s.box.separation(start_position(ctx, start, i), start_position(ctx, start, j)) / ctx.length_scale;
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

template <int D>
GroupSolution<D> solve_rigid(const ProblemContext<D>& ctx, const CollisionGroup& g, const GroupStart& start) {
  const State<D>& s = ctx.state;
  auto variable = [&](int sphere) {
    const int c = s.spheres.cluster[sphere];
    return static_cast<int>(std::lower_bound(g.clusters.begin(), g.clusters.end(), c) - g.clusters.begin());
  };
  DahaProblem<D> prob;
  for (int c : g.clusters) prob.inverse_mass.push_back(ctx.mean_mass / s.clusters[c].mass);
  std::vector<int> touching;
  for (int idx : g.pairs) {
    const SpherePair& p = ctx.S[idx];
    prob.pairs.push_back(make_pair(ctx, start, p.i, p.j, variable(p.i), variable(p.j), p.lambda));
    touching.push_back(p.i);
    touching.push_back(p.j);
  }
  std::sort(touching.begin(), touching.end());
  prob.n_spheres = static_cast<int>(std::unique(touching.begin(), touching.end()) - touching.begin());

  GroupSolution<D> out;
  std::vector<Vec<D>> u;
  out.result = minimise(prob, ctx.settings.daha, u);
  out.n_variables = static_cast<int>(g.clusters.size());
  for (const DahaPair<D>& q : prob.pairs) out.pair_lambda.push_back(q.lambda);
  for (std::size_t k = 0; k < g.clusters.size(); ++k) {
    const Cluster<D>& cluster = s.clusters[g.clusters[k]];
    const Vec<D> shift = shift_from_start(ctx, start, cluster.members.front(), u[k]);
    if (shift == Vec<D>::Zero()) continue;
    for (int m : cluster.members) {
      out.spheres.push_back(m);
      out.shift.push_back(shift);
    }
  }
  return out;
}

// Start positions of the group's spheres, unwrapped (one image of the whole group, even
// when it is wider than a periodic box): within an old cluster from the body offsets, and
// from cluster to cluster across the pairs of S that join them.
template <int D>
std::vector<Vec<D>> unwrapped_starts(const ProblemContext<D>& ctx, const CollisionGroup& g, const GroupStart& start,
                                     const std::vector<int>& spheres, const std::unordered_map<int, int>& local) {
  const State<D>& s = ctx.state;
  auto moved = [&](int i) { return start.backtrack ? Vec<D>::Zero() : ctx.step_shift[i]; };
  std::vector<Vec<D>> x(spheres.size());
  std::vector<char> placed(g.clusters.size(), 0);
  auto place = [&](int c_index, int known_sphere, const Vec<D>& at) {
    for (int m : s.clusters[g.clusters[c_index]].members)
      x[local.at(m)] = at + (s.spheres.offset[m] + moved(m)) - (s.spheres.offset[known_sphere] + moved(known_sphere));
    placed[c_index] = 1;
  };
  auto index_of = [&](int sphere) {
    return static_cast<int>(std::lower_bound(g.clusters.begin(), g.clusters.end(), s.spheres.cluster[sphere]) -
                            g.clusters.begin());
  };
  const int first = s.clusters[g.clusters[0]].members.front();
  place(0, first, start_position(ctx, start, first));
  for (bool progress = true; progress;) {  // a few sweeps: groups are small trees of clusters
    progress = false;
    for (int idx : g.pairs) {
      const SpherePair& p = ctx.S[idx];
      const int a = index_of(p.i), b = index_of(p.j);
      if (placed[a] == placed[b]) continue;
      const int from = placed[a] ? p.i : p.j, to = placed[a] ? p.j : p.i;
      const Vec<D> hop = s.box.separation(start_position(ctx, start, to), start_position(ctx, start, from));
      place(placed[a] ? b : a, to, x[local.at(from)] + hop);
      progress = true;
    }
  }
  return x;
}

// Non-rigid and almost-rigid: one variable per sphere of the group. Constraints on S, on
// the old links and on every pair close enough to come into contact; attraction over all
// pairs (non-rigid) or over the pairs within Delta_W (almost-rigid).
template <int D>
GroupSolution<D> solve_per_sphere(const ProblemContext<D>& ctx, const CollisionGroup& g, const GroupStart& start) {
  const State<D>& s = ctx.state;
  std::vector<int> spheres;
  for (int c : g.clusters) spheres.insert(spheres.end(), s.clusters[c].members.begin(), s.clusters[c].members.end());
  std::unordered_map<int, int> local;
  local.reserve(spheres.size());
  for (std::size_t a = 0; a < spheres.size(); ++a) local.emplace(spheres[a], static_cast<int>(a));

  DahaProblem<D> prob;
  prob.n_spheres = static_cast<int>(spheres.size());
  for (int i : spheres) prob.inverse_mass.push_back(ctx.mean_mass / s.spheres.mass[i]);
  const bool local_attraction = ctx.settings.model == TsModel::almost_rigid;
  prob.range = ctx.delta_w / ctx.length_scale;
  if (!local_attraction) {
    for (const Vec<D>& x : unwrapped_starts(ctx, g, start, spheres, local)) prob.position.push_back(x / ctx.length_scale);
  }
  // Almost-rigid: cells of side Delta_W (the "rectangles" of §3.3) over the group's
  // spheres find the pairs within range. Only the spheres within Delta_W of a sphere of a
  // new contact move; the rest of each old cluster holds still (zero inverse mass), so a
  // cluster deforms only near the impact ("elasticity admitted but only locally").
  std::vector<Vec<D>> x;
  for (int i : spheres) x.push_back(s.box.wrap(start_position(ctx, start, i)));
  const double reach = local_attraction ? (1.0 + kRangeMargin) * ctx.delta_w : (2.0 + kContactMargin) * s.max_radius();
  SortedCellList<D> cells(s.box, reach, static_cast<int>(x.size()));
  cells.build(x);
  std::vector<char> mobile(spheres.size(), local_attraction ? 0 : 1);
  if (local_attraction) {
    for (int idx : g.pairs)
      for (int i : {ctx.S[idx].i, ctx.S[idx].j}) {
        const Vec<D>& xi = x[local.at(i)];
        cells.for_each_near(xi, [&](int b) {
          if (s.box.separation(xi, x[b]).norm() <= reach) mobile[b] = 1;
        });
      }
    prob.n_spheres = static_cast<int>(std::count(mobile.begin(), mobile.end(), 1));
    for (std::size_t a = 0; a < spheres.size(); ++a)
      if (!mobile[a]) prob.inverse_mass[a] = 0.0;
  }

  std::unordered_map<std::uint64_t, int> index;  // pair key -> position in prob.pairs
  auto add = [&](int i, int j, double lambda) {
    const int a = local.at(i), b = local.at(j);
    if (!mobile[a] && !mobile[b]) return;
    if (!index.emplace(key(i, j), static_cast<int>(prob.pairs.size())).second) return;
    DahaPair<D> q = make_pair(ctx, start, i, j, a, b, lambda);
    q.attract = local_attraction;  // non-rigid: the attraction is the all-pairs term
    q.attract_within_range = local_attraction;
    prob.pairs.push_back(q);
  };
  for (int idx : g.pairs) add(ctx.S[idx].i, ctx.S[idx].j, ctx.S[idx].lambda);  // groups list active pairs only
  const std::size_t first_link = prob.pairs.size();
  std::vector<SpherePair> links;
  for (int i : spheres)
    for (const LinkEnd& e : ctx.links.of(i)) {
      if (!mobile[local.at(i)] && !mobile[local.at(e.other)]) continue;
      links.push_back({i, e.other, e.lambda});
      add(i, e.other, e.lambda);
    }
  const std::size_t last_link = prob.pairs.size();
  for (std::size_t a = 0; a < x.size(); ++a)
    cells.for_each_near(x[a], [&](int b) {
      if (b > static_cast<int>(a) && s.box.separation(x[a], x[b]).squaredNorm() <= reach * reach)
        add(spheres[a], spheres[b], 0.0);
    });

  GroupSolution<D> out;
  std::vector<Vec<D>> u;
  out.result = minimise(prob, ctx.settings.daha, u);
  out.n_variables = prob.n_spheres;
  out.link_stretch = largest_stretch(prob, u, first_link, last_link);
  for (std::size_t p = 0; p < first_link; ++p) out.pair_lambda.push_back(prob.pairs[p].lambda);
  for (SpherePair& l : links) l.lambda = prob.pairs[index.at(key(l.i, l.j))].lambda;
  out.old_links = std::move(links);
  for (std::size_t a = 0; a < spheres.size(); ++a) {
    const Vec<D> shift = shift_from_start(ctx, start, spheres[a], u[a]);
    if (shift == Vec<D>::Zero()) continue;
    out.spheres.push_back(spheres[a]);
    out.shift.push_back(shift);
  }
  return out;
}

// A pair of spheres of different old clusters of a group whose separation, as the group
// is moved back by the fraction theta of this step's flight, is base - theta * drift.
template <int D>
struct RetreatPair {
  SpherePair pair;
  Vec<D> base, drift;
  double sigma;
  double overlap(double theta) const { return 1.0 - (base - theta * drift).norm() / sigma; }
};

// Every pair of spheres of different clusters of the group that can touch while the group
// retreats through its whole flight. Found from the spheres of all but the largest cluster
// with the step's cell list, so that a giant cluster hit by a monomer costs nothing.
template <int D>
std::vector<RetreatPair<D>> retreat_pairs(const ProblemContext<D>& ctx, const CollisionGroup& g) {
  const State<D>& s = ctx.state;
  int largest = g.clusters[0];
  double longest_flight = 0.0, longest_shift = 0.0;  // the query is made at current positions
  for (int c : g.clusters) {
    if (s.clusters[c].size() > s.clusters[largest].size()) largest = c;
    longest_flight = std::max(longest_flight, ctx.flight[c].norm());
    for (int i : s.clusters[c].members) longest_shift = std::max(longest_shift, ctx.step_shift[i].norm());
  }
  const double reach = 2.0 * s.max_radius() + 2.0 * longest_flight;
  const GroupStart at_end{true, 0.0};
  auto in_group = [&](int c) { return std::binary_search(g.clusters.begin(), g.clusters.end(), c); };
  std::vector<RetreatPair<D>> out;
  for (int c : g.clusters) {
    if (c == largest) continue;
    for (int i : s.clusters[c].members) {
      const Vec<D> xi = start_position(ctx, at_end, i);
      ctx.cells.for_each_within(ctx.positions[i], reach + 2.0 * (ctx.cell_slack + longest_shift), [&](int j) {
        const int cj = s.spheres.cluster[j];
        if (cj == c || !in_group(cj) || (cj != largest && j < i)) return;  // each pair once
        const Vec<D> base = s.box.separation(xi, start_position(ctx, at_end, j));
        if (base.norm() > reach) return;
        out.push_back({SpherePair{std::min(i, j), std::max(i, j), 0.0}, base, ctx.flight[c] - ctx.flight[cj],
                       s.spheres.radius[i] + s.spheres.radius[j]});
      });
    }
  }
  return out;
}

// Bisection steps of place_at_contact: the instant is found to 2^-kBisections of the step.
constexpr int kBisections = 32;

}  // namespace

template <int D>
GroupSolution<D> place_at_contact(const ProblemContext<D>& ctx, const CollisionGroup& g) {
  const State<D>& s = ctx.state;
  const std::vector<RetreatPair<D>> pairs = retreat_pairs(ctx, g);
  const double tolerance = 0.5 * ctx.settings.daha.eps_c;
  auto worst = [&](double theta) {
    double w = -1.0;
    for (const RetreatPair<D>& p : pairs) w = std::max(w, p.overlap(theta));
    return w;
  };
  // Overlapping already at the start of the step (by at most eps_c, or more after a step
  // that ran out of link rounds): aim at no worse than that.
  const double target = std::max(tolerance, worst(1.0));
  double lo = 0.0, hi = 1.0;  // overlap too deep at lo; acceptable at hi (the start of the step)
  if (worst(lo) <= target) hi = lo;
  for (int k = 0; k < kBisections && hi > lo; ++k) {
    const double mid = 0.5 * (lo + hi);
    (worst(mid) <= target ? hi : lo) = mid;
  }
  const GroupStart start{true, hi};
  GroupSolution<D> out;
  out.placed_at_contact = true;
  out.n_variables = static_cast<int>(g.clusters.size());
  for (const RetreatPair<D>& p : pairs) {
    const double overlap = p.overlap(hi);
    if (overlap < -ctx.settings.daha.eps_c) continue;  // touching: d <= sigma (1 + eps_c)
    out.contacts.push_back(p.pair);
    out.result.residual_overlap = std::max(out.result.residual_overlap, overlap);
  }
  out.result.converged = true;
  for (int c : g.clusters)
    for (int i : s.clusters[c].members) {
      const Vec<D> shift = shift_from_start<D>(ctx, start, i, Vec<D>::Zero());
      if (shift == Vec<D>::Zero()) continue;
      out.spheres.push_back(i);
      out.shift.push_back(shift);
    }
  return out;
}

template <int D>
GroupSolution<D> solve_group(const ProblemContext<D>& ctx, const CollisionGroup& group, GroupStart start) {
  if (ctx.settings.model == TsModel::rigid) return solve_rigid(ctx, group, start);
  return solve_per_sphere(ctx, group, start);
}

template GroupSolution<2> solve_group<2>(const ProblemContext<2>&, const CollisionGroup&, GroupStart);
template GroupSolution<3> solve_group<3>(const ProblemContext<3>&, const CollisionGroup&, GroupStart);
template GroupSolution<2> place_at_contact<2>(const ProblemContext<2>&, const CollisionGroup&);
template GroupSolution<3> place_at_contact<3>(const ProblemContext<3>&, const CollisionGroup&);

}  // namespace ballagg
