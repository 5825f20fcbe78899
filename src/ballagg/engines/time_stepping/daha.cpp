#include "ballagg/engines/time_stepping/daha.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ballagg {
namespace {

// The fraction of its best value the worst violation must fall to, to count as progress
// for stall_iterations: a tenth less, so that slow creeping does not count as converging.
constexpr double kStallProgress = 0.9;

// Inverse masses within this fraction above 1 count as 1 (stable_inverse_masses): the
// rounding of a mean of equal masses (at most about 1e-16 per sphere summed, so 1e-8 at
// 10^8 spheres), far below any mass ratio that matters to stability.
constexpr double kMeanMassRounding = 1e-6;

// Overlap statistics that drive the dynamical parameters (3.29).
struct OverlapStats {
  std::vector<double> sum, count;  // per variable; empty when the damping is constant
  double mean = 0.0;               // phi_A: mean relative overlap over all pairs
  double max = 0.0;
};

template <int D>
Vec<D> separation(const DahaPair<D>& q, const std::vector<Vec<D>>& u) {
  return q.base + u[q.a] - u[q.b];
}

// Multiplier update (3.24) at the new positions, and the overlaps for the next iteration.
template <int D>
void update_multipliers(DahaProblem<D>& prob, const std::vector<Vec<D>>& u, double beta, bool printed,
                        OverlapStats& s) {
  const bool per_variable = !s.sum.empty();
  std::fill(s.sum.begin(), s.sum.end(), 0.0);
  std::fill(s.count.begin(), s.count.end(), 0.0);
  double total = 0.0;
  s.max = 0.0;
  double counted = 0.0;
  for (DahaPair<D>& q : prob.pairs) {
    const Vec<D> d = separation(q, u);
    const double phi = q.sigma * q.sigma - d.squaredNorm();  // smooth constraint (3.4)
    q.lambda = std::max(0.0, q.lambda + beta * phi);
    double rho = 0.0;  // relative overlap, 1 - |d| / sigma when positive
    if (phi > 0.0 || q.lambda > 0.0) {
      const double gap = 1.0 - d.norm() / q.sigma;
      rho = std::max(0.0, gap);
      // (3.28) read with complementarity: a constraint carrying a multiplier must hold as
      // an equality (touching, |1 - d / sigma| small), one without only as an inequality.
      // As printed, only the overlap counts.
      s.max = std::max(s.max, q.lambda > 0.0 && !printed ? std::abs(gap) : rho);
    } else if (q.guard) {
      continue;  // an idle guard: apart, without a multiplier
    }
    if (q.stretch_limit < std::numeric_limits<double>::infinity()) {  // a bond's upper bound
      const double psi = d.squaredNorm() - q.stretch_limit * q.stretch_limit;
      q.mu = std::max(0.0, q.mu + beta * psi);
      if (psi > 0.0 || q.mu > 0.0) {
        const double stretch = d.norm() / q.stretch_limit - 1.0;
        s.max = std::max(s.max, q.mu > 0.0 ? std::abs(stretch) : std::max(0.0, stretch));
      }
    }
    if (per_variable) {
      s.sum[q.a] += rho;
      s.sum[q.b] += rho;
      s.count[q.a] += 1.0;
      s.count[q.b] += 1.0;
    }
    total += rho;
    counted += 1.0;
  }
  s.mean = counted > 0.0 ? total / counted : 0.0;
}

// The all-pairs potential of the non-rigid model, (3.5) with S every pair of the new
// cluster: grad_a W = sum_b (X_a - X_b) = n (X_a - mean X).
template <int D>
void add_global_attraction(const DahaProblem<D>& prob, const std::vector<Vec<D>>& u, double alpha,
                           std::vector<Vec<D>>& force, std::vector<double>& stiffness) {
  const int n = static_cast<int>(u.size());
  Vec<D> mean = Vec<D>::Zero();
  for (int k = 0; k < n; ++k) mean += prob.position[k] + u[k];
  mean /= n;
  for (int k = 0; k < n; ++k) {
    force[k] -= alpha * n * (prob.position[k] + u[k] - mean);
    stiffness[k] += alpha * n;
  }
}

// Projects the variables on the walls' bounds (prob.lower/upper): a variable stopped by a
// wall keeps no velocity into it. Without it a minimisation pushes clusters through the
// walls, and a cluster grown across the box that way ends wider than the box.
template <int D>
void keep_within_walls(const DahaProblem<D>& prob, std::vector<Vec<D>>& u, std::vector<Vec<D>>& velocity) {
  if (prob.lower.empty()) return;
  for (std::size_t k = 0; k < u.size(); ++k)
    for (int a = 0; a < D; ++a) {
      if (u[k][a] < prob.lower[k][a]) {
        u[k][a] = prob.lower[k][a];
        velocity[k][a] = std::max(0.0, velocity[k][a]);
      } else if (u[k][a] > prob.upper[k][a]) {
        u[k][a] = prob.upper[k][a];
        velocity[k][a] = std::min(0.0, velocity[k][a]);
      }
    }
}

// (3.26): lambda = lambda0 max(0, phi) for a pair without a stored multiplier; the same
// for a bond's upper bound.
template <int D>
void initial_multipliers(DahaProblem<D>& prob, const DahaParameters& p) {
  for (DahaPair<D>& q : prob.pairs) {
    if (q.lambda == 0.0) q.lambda = p.lambda0 * std::max(0.0, q.sigma * q.sigma - q.base.squaredNorm());
    if (q.mu == 0.0 && q.stretch_limit < std::numeric_limits<double>::infinity())
      q.mu = p.lambda0 * std::max(0.0, q.base.squaredNorm() - q.stretch_limit * q.stretch_limit);
  }
}

// (3.21)'s forces of the pairs at X^{r+1/2}: F_a = -alpha (grad_a W + lambda grad_a phi)
// - gamma phi lambda grad_a phi, with grad_a W = d for an attracting pair and grad_a phi =
// -2 d, d = X_a - X_b; and each variable's stiffness, the sum over its pairs of |dF/dd|.
template <int D>
void add_pair_forces(const DahaProblem<D>& prob, const DahaParameters& p, const std::vector<Vec<D>>& u,
                     std::vector<Vec<D>>& force, std::vector<double>& stiffness) {
  const double range2 = prob.range * prob.range;
  for (const DahaPair<D>& q : prob.pairs) {
    if (!q.attract && q.lambda == 0.0 && q.mu == 0.0) continue;  // no force: nothing active
    const Vec<D> d = separation(q, u);
    const double d2 = d.squaredNorm();
    const double phi = q.sigma * q.sigma - d2;
    const bool attract = q.attract && (!q.attract_within_range || d2 <= range2);
    const double coefficient = (attract ? -p.alpha : 0.0) + 2.0 * q.lambda * (p.alpha + p.gamma * phi);
    force[q.a] += coefficient * d;
    force[q.b] -= coefficient * d;
    double k = std::abs(coefficient) + 4.0 * p.gamma * q.lambda * d2;
    if (q.mu > 0.0) {
      // The bond's bound: -alpha mu grad psi - gamma psi mu grad psi, grad_a psi = 2 d.
      const double psi = d2 - q.stretch_limit * q.stretch_limit;
      const double pull = -2.0 * q.mu * (p.alpha + p.gamma * psi);
      force[q.a] += pull * d;
      force[q.b] -= pull * d;
      k += std::abs(pull) + 4.0 * p.gamma * q.mu * d2;
    }
    stiffness[q.a] += k;
    stiffness[q.b] += k;
  }
}

// The inverse masses the velocity update (3.21) uses: the problem's (in mean sphere
// masses), or, when a variable of the problem is lighter than the mean sphere, in units of
// the lightest variable.
//
// Why: linearise a variable against a fixed partner, F = -K x along the pair. With the
// update's gain g = w K (w = inverse mass / max(1, stiffness), below), one iteration
// (3.20)-(3.23) maps (x, v) by a matrix of determinant 1 - c and trace
// 2 - c - delta (1 - c) g, stable if and only if g < 2 (2 - c) / (delta (1 - c)): 1.43 for
// the rigid model's defaults, 1.91 for the per-sphere ones. A variable's stiffness sums
// the |dF/dd| of its pairs, so K <= stiffness and g <= its inverse mass. With equal masses
// no variable is lighter than a sphere, g <= 1, and the parameters are tuned there (the
// fastest sets lie near the bound). A sphere ten times lighter than the
// mean would take g up to 10, and its velocity would grow 17-fold per iteration (rigid
// defaults) until it overflowed. Dividing every inverse mass of the problem by the largest
// keeps every gain within the tuned ones whatever the mass ratio, and keeps the ratios:
// heavy variables still move less than light ones in proportion (the centre of mass of two
// bodies stays where free flight put it), and the fixed variable (inverse mass 0) stays.
// The solutions (zero forces) are unchanged; a problem with a light variable takes the
// iterations of one whose lightest variable is a mean sphere.
std::vector<double> stable_inverse_masses(const std::vector<double>& inverse_mass) {
  std::vector<double> w = inverse_mass;
  const double largest = w.empty() ? 0.0 : *std::max_element(w.begin(), w.end());
  if (largest > 1.0 + kMeanMassRounding)
    for (double& x : w) x /= largest;
  return w;
}

// The iterates of the DAHA and what one iteration works with.
template <int D>
struct DahaIterate {
  DahaIterate(const std::vector<double>& problem_inverse_mass, bool per_variable_damping)
      : velocity(problem_inverse_mass.size(), Vec<D>::Zero()),
        force(problem_inverse_mass.size()),
        previous(problem_inverse_mass.size()),
        stiffness(problem_inverse_mass.size()),
        inverse_mass(stable_inverse_masses(problem_inverse_mass)),
        stats{std::vector<double>(per_variable_damping ? problem_inverse_mass.size() : 0),
              std::vector<double>(per_variable_damping ? problem_inverse_mass.size() : 0)} {}
  std::vector<Vec<D>> velocity, force, previous;
  // Diagonal (Jacobi) scaling: the force on a variable held by stiff constraints (many of
  // them, or large multipliers) changes fast with its position, and the explicit update
  // would oscillate without bound. Each variable's force is divided by its stiffness
  // (when above 1); the steady states (zero force), and so the solutions, are unchanged.
  std::vector<double> stiffness;
  std::vector<double> inverse_mass;  // stable_inverse_masses of the problem's
  OverlapStats stats;
};

// (3.20): X^{r+1/2} = X^r + delta / 2 V^r, and the forces cleared.
template <int D>
void half_step_positions(std::vector<Vec<D>>& u, DahaIterate<D>& it, double half) {
  for (std::size_t k = 0; k < u.size(); ++k) {
    u[k] += half * it.velocity[k];
    it.force[k].setZero();
    it.stiffness[k] = 0.0;
  }
}

// (3.21) the velocity update by the scaled force, (3.22) the damping c_i of (3.29), and
// (3.23) X^{r+1} = X^{r+1/2} + delta / 2 V^{r+1}.
template <int D>
void damped_velocity_step(const DahaParameters& p, std::vector<Vec<D>>& u, DahaIterate<D>& it, double half) {
  const bool per_variable_damping = !it.stats.sum.empty();
  for (std::size_t k = 0; k < u.size(); ++k) {
    it.velocity[k] += it.inverse_mass[k] / std::max(1.0, it.stiffness[k]) * it.force[k];
    double c = p.c_max;
    if (per_variable_damping) {
      const double own = it.stats.count[k] > 0.0 ? it.stats.sum[k] / it.stats.count[k] : 0.0;
      c = dynamic_damping(p, p.delta * it.velocity[k].norm(), own, it.stats.mean);
    }
    it.velocity[k] *= 1.0 - c;          // (3.22)
    u[k] += half * it.velocity[k];      // (3.23)
  }
}

// (3.27), per variable, in units of the length scale: the largest of the squared moves,
// one square root (the same value as the largest of the norms). A move that is not a
// number makes the result one (std::max would skip it), so that an iteration that has
// diverged never passes (3.27): the overlaps of (3.28) skip such pairs too.
template <int D>
double largest_move(const std::vector<Vec<D>>& u, const std::vector<Vec<D>>& previous) {
  double largest_squared_move = 0.0;
  for (std::size_t k = 0; k < u.size(); ++k) {
    const double squared_move = (u[k] - previous[k]).squaredNorm();
    if (squared_move > largest_squared_move || std::isnan(squared_move)) largest_squared_move = squared_move;
  }
  return std::sqrt(largest_squared_move);
}

// (3.27) as printed: |X^{r+1} - X^r| / |X^r|, the norms of the vectors of all the
// problem's positions (X^r = start + u^r, from the box's corner: the measure depends on
// where the origin is, as printed). Infinite while |X^r| = 0.
template <int D>
double relative_move(const DahaProblem<D>& prob, const std::vector<Vec<D>>& u, const std::vector<Vec<D>>& previous) {
  double moved = 0.0, size = 0.0;
  for (std::size_t k = 0; k < u.size(); ++k) {
    moved += (u[k] - previous[k]).squaredNorm();
    size += ((k < prob.start.size() ? prob.start[k] : Vec<D>::Zero()) + previous[k]).squaredNorm();
  }
  return size > 0.0 ? std::sqrt(moved / size) : std::numeric_limits<double>::infinity();
}

// (3.27)-(3.28): whether the iteration may stop.
template <int D>
bool stopping_conditions_met(const DahaProblem<D>& prob, const DahaParameters& p, const std::vector<Vec<D>>& u,
                             const DahaIterate<D>& it) {
  if (it.stats.max > p.eps_c) return false;
  return (p.printed_stopping ? relative_move(prob, u, it.previous) : largest_move(u, it.previous)) <= p.eps_s;
}

// Progress watch for stall_iterations: the best worst-violation so far, and when it fell.
struct StallWatch {
  double best_violation;
  int best_at = 0;
  // Whether the minimisation has stalled at this iteration.
  bool stalled(const DahaParameters& p, double violation, int iteration) {
    if (violation < kStallProgress * best_violation || violation <= p.eps_c) {
      best_violation = std::min(best_violation, violation);
      best_at = iteration;
      return false;
    }
    return p.stall_iterations > 0 && iteration - best_at >= p.stall_iterations;
  }
};

}  // namespace

// (3.29), beta = beta-bar sqrt(N) / phi_A: multipliers grow faster as the overlaps shrink
// and as more spheres take part; capped, and at the cap when nothing overlaps.
double dynamic_beta(const DahaParameters& p, int n_spheres, double mean_overlap) {
  if (mean_overlap <= 0.0) return p.beta_max;
  return std::min(p.beta_max, p.beta_bar * std::sqrt(static_cast<double>(n_spheres)) / mean_overlap);
}

// (3.29), c_i = c-bar |delta |V_i| - phi_i^A| / phi_A: damping grows as the mean overlap
// shrinks, and when a variable moves much more (or less) per step than its own overlap.
double dynamic_damping(const DahaParameters& p, double step_length, double own_overlap, double mean_overlap) {
  if (mean_overlap <= 0.0) return p.c_max;
  return std::clamp(p.c_bar * std::abs(step_length - own_overlap) / mean_overlap, p.c_min, p.c_max);
}

// One iteration r -> r + 1 is (3.20)-(3.24); it stops on (3.27)-(3.28), at max_iterations,
// when stalled, or when the run's guard says the step must end.
template <int D>
DahaResult minimise(DahaProblem<D>& prob, const DahaParameters& p, std::vector<Vec<D>>& u, const RunGuard* guard) {
  const int n_vars = static_cast<int>(prob.inverse_mass.size());
  u.assign(n_vars, Vec<D>::Zero());
  // With c_min = c_max (the defaults) every variable's damping is that value, whatever
  // (3.29) gives before clamping: the per-variable overlaps and step lengths it reads are
  // then neither gathered nor computed (the same iterates, sooner).
  DahaIterate<D> it(prob.inverse_mass, p.c_min < p.c_max);
  initial_multipliers(prob, p);
  update_multipliers(prob, u, 0.0, p.printed_stopping, it.stats);  // beta = 0: statistics only
  DahaResult result;
  const double half = 0.5 * p.delta;
  StallWatch watch{it.stats.max};
  while (result.iterations < p.max_iterations) {
    if (guard != nullptr && result.iterations % kIterationsPerGuardCheck == kIterationsPerGuardCheck - 1 &&
        guard->step_must_end())
      break;
    ++result.iterations;
    it.previous = u;
    half_step_positions(u, it, half);  // (3.20)
    keep_within_walls(prob, u, it.velocity);
    if (!prob.position.empty()) add_global_attraction(prob, u, p.alpha, it.force, it.stiffness);
    add_pair_forces(prob, p, u, it.force, it.stiffness);  // (3.21)
    damped_velocity_step(p, u, it, half);                  // (3.21)-(3.23)
    keep_within_walls(prob, u, it.velocity);
    update_multipliers(prob, u, dynamic_beta(p, prob.n_spheres, it.stats.mean), p.printed_stopping, it.stats);  // (3.24)
    result.converged = stopping_conditions_met(prob, p, u, it);  // (3.27), (3.28)
    if (result.converged) break;
    if (watch.stalled(p, it.stats.max, result.iterations)) break;
  }
  result.residual_overlap = it.stats.max;
  return result;
}

template DahaResult minimise<2>(DahaProblem<2>&, const DahaParameters&, std::vector<Vec<2>>&, const RunGuard*);
template DahaResult minimise<3>(DahaProblem<3>&, const DahaParameters&, std::vector<Vec<3>>&, const RunGuard*);

}  // namespace ballagg
