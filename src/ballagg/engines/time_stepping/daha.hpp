#pragma once
// The damped Arrow–Hurwicz algorithm (DAHA, paper §3.2): finds a configuration near the
// given one that minimises the adhesion potential W under non-overlap constraints, by a
// damped second-order dynamics of the positions coupled to projected ascent of the
// Lagrange multipliers, eqs (3.20)-(3.24), with the initial condition (3.26), the stopping
// conditions (3.27)-(3.28) and the dynamical parameters (3.29).
//
// The unknowns are displacements u_k, one per *variable*: a sphere (non-rigid and almost-
// rigid models) or a whole old cluster (rigid model). Sphere a sits at base_a + u_{var(a)};
// only differences of positions enter, so a pair is described by its base separation
// (minimum image, taken once) and the problem never sees the periodic box.
//
// Units: every length is divided by the problem's length scale (the mean contact distance),
// so that the parameters are dimensionless. docs/time_stepping.md derives the update from
// the physics where the extracted formulas are garbled.
#include <cstdint>
#include <limits>
#include <vector>

#include "ballagg/core/run_guard.hpp"
#include "ballagg/core/vec.hpp"
#include "ballagg/engines/time_stepping/ts_settings.hpp"

namespace ballagg {

template <int D>
struct DahaPair {
  std::int32_t a = 0, b = 0;          // variables of the two spheres (a != b)
  Vec<D> base = Vec<D>::Zero();       // X_a - X_b before the minimisation (scaled)
  double sigma = 1.0;                 // contact distance R_a + R_b (scaled)
  double lambda = 0.0;                // Lagrange multiplier, in and out (warm start)
  bool attract = true;                // in the potential W (links; pairs within Delta_W)
  bool attract_within_range = false;  // almost-rigid: W term only while |d| <= range (H_W)
  // A guard: a pair outside S, constrained so that the minimisation does not push spheres
  // into their neighbours. It enters the mean overlap of (3.29) only while it is active
  // (overlapping or carrying a multiplier), so guards do not dilute the statistics.
  bool guard = false;
  // A bond: also |d| <= stretch_limit (scaled), the constraint psi = |d|^2 - limit^2 <= 0
  // with its own multiplier mu, treated like phi (the almost-rigid model's links).
  // Infinite: no upper bound.
  double stretch_limit = std::numeric_limits<double>::infinity();
  double mu = 0.0;
};

template <int D>
struct DahaProblem {
  // Per variable, relative to the mean sphere mass (the minimiser measures them in units of
  // the lightest variable when that is lighter: stable_inverse_masses in daha.cpp). A
  // variable with inverse mass 0 never moves: spheres that stay where they are (neighbours
  // outside the problem) are pairs with such a variable.
  std::vector<double> inverse_mass;
  std::vector<DahaPair<D>> pairs;
  // Non-rigid model: W = 1/2 sum over all pairs of variables of |X_a - X_b|^2, whose
  // gradient n (X_a - mean X) costs O(n); `position` holds the starting X_a (scaled,
  // unwrapped). Empty: no such term.
  std::vector<Vec<D>> position;
  // Walls: per variable, the box of displacements (scaled) that keeps its spheres between
  // the walls; empty: no bounds (periodic boxes). The minimiser projects on it.
  std::vector<Vec<D>> lower, upper;
  // Per variable, where it starts (scaled, from the box's corner): the |X^r| of (3.27) as
  // printed (DahaParameters::printed_stopping); unused otherwise.
  std::vector<Vec<D>> start;
  double range = 0.0;                 // Delta_W (scaled), for attract_within_range pairs
  int n_spheres = 0;                  // spheres involved: the sqrt(N) of (3.29)
};

// Receives a copy of every problem the engine hands to the minimiser, before it is solved:
// the seam through which bench/daha_tune records problems from real runs to tune the
// parameters offline. Called from several threads at once.
template <int D>
class DahaProblemSink {
 public:
  virtual ~DahaProblemSink() = default;
  virtual void record(const DahaProblem<D>& problem) = 0;
};

struct DahaResult {
  int iterations = 0;
  bool converged = false;             // both stopping conditions met before max_iterations
  double residual_overlap = 0.0;      // max over pairs of 1 - d / sigma at the end
};

// The dynamical parameters (3.29) of one iteration: beta from the number of spheres of the
// problem and the mean relative overlap phi_A of its pairs, capped at beta_max; c_i from
// the variable's step length delta |V_i| and its own mean overlap phi_i^A (diameters and
// relative overlaps), clamped to [c_min, c_max]. Both at their cap when nothing overlaps.
double dynamic_beta(const DahaParameters& p, int n_spheres, double mean_overlap);
double dynamic_damping(const DahaParameters& p, double step_length, double own_overlap, double mean_overlap);

// Iterations between two questions to the run's guard (RunGuard::step_must_end reads a
// clock, which costs about as much as an iteration of the smallest problem).
inline constexpr int kIterationsPerGuardCheck = 64;

// Solves the problem; returns the displacements (scaled) in `u` (resized to the number of
// variables) and the final multipliers in problem.pairs[].lambda. With a guard, stops
// unconverged (as at max_iterations) once the guard says the step must end.
template <int D>
DahaResult minimise(DahaProblem<D>& problem, const DahaParameters& p, std::vector<Vec<D>>& u,
                    const RunGuard* guard = nullptr);

extern template DahaResult minimise<2>(DahaProblem<2>&, const DahaParameters&, std::vector<Vec<2>>&, const RunGuard*);
extern template DahaResult minimise<3>(DahaProblem<3>&, const DahaParameters&, std::vector<Vec<3>>&, const RunGuard*);

}  // namespace ballagg
