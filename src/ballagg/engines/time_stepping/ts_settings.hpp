#pragma once
// Parameters of the time-stepping engine (paper §3) and of its damped Arrow–Hurwicz
// minimiser (DAHA, §3.2). Every number is dimensionless: lengths inside the minimiser are
// measured in units of the mean contact distance 2 <R>, times in units of the step delta.
// docs/time_stepping.md gives the meaning of each, how the defaults were tuned, and where
// the machine-extracted formulas of the paper had to be re-derived.
#include <optional>
#include <string_view>

namespace ballagg {

// How clusters formed at earlier steps behave during the minimisation.
enum class TsModel {
  rigid,         // one displacement per old cluster (ours, closest to event-driven dynamics)
  almost_rigid,  // every sphere moves; local attraction within delta_w, eqs (3.30)-(3.31)
  non_rigid,     // every sphere moves; attraction along the adhesive links, eq (3.5)
};

// How the free-flight step is chosen.
enum class TsDtRule {
  growth,    // dt(0) = dt_factor L / max|V_i|, growing to dt_growth dt(0) at one cluster (Table 1)
  adaptive,  // dt = R_max / max_k |V_Ck| at every step, eq (3.3)
};

// Which method the engine runs (docs/time_stepping.md).
enum class TsMethod {
  ours,   // the engine's loop: step bodies, guards, the fall-back, settling; tuned DAHA constants
  paper,  // the paper's method as printed (per-sphere models only): no fall-back, no rigid
          // remainder, no bond cap, (3.27)-(3.28) as printed, (3.29) active; a minimisation
          // that never meets (3.28) is counted and its iterate accepted
};

// What happens to a group the minimisation does not solve (the fall-back).
enum class TsFallBack {
  retreat,      // back along the flights to the last instant nothing overlaps; the rest of the flight is lost
  keep_flight,  // the same, then on to the end of the step, merging at each contact (flight_sweep.hpp)
};

// The defaults below are the rigid model's: the values that solve the minimisation
// problems recorded from large rigid runs in the fewest iterations (bench/daha_tune;
// docs/time_stepping.md, "Parameters"). default_daha gives each model its own.
struct DahaParameters {
  double alpha = 0.0531;      // alpha~ of (3.21): weight of the Lagrangian gradient in a velocity update
  double gamma = 0.158;       // gamma~ of (3.21): weight of the phi * lambda * grad phi term
  double delta = 5.95;        // delta of (3.20), (3.23): the artificial time step
  double c_bar = 0.018;       // c-bar of (3.29): damping scale
  double c_min = 0.694;       // lower bound of c_i: keeps the dynamics damped (stability, docs)
  double c_max = 0.694;       // upper bound of the damping c_i (1 would freeze the spheres)
  double beta_bar = 0.602;    // beta-bar of (3.29): multiplier growth scale
  double beta_max = 0.345;    // upper bound of beta (reached when no constraint is violated)
  double lambda0 = 0.199;     // lambda of (3.26): initial multiplier per unit overlap phi
  double eps_s = 1e-4;        // (3.27): largest move of a sphere in one iteration, in diameters
  double eps_c = 1e-3;        // (3.28): largest relative overlap left, 1 - d / (R_i + R_j)
  int max_iterations = 3000;  // per minimisation; reaching it is counted, not an error
  // A minimisation whose worst constraint violation (above eps_c) has not fallen below 0.9
  // of its best for this many iterations is given up (0: never): it is not converging.
  int stall_iterations = 310;
  // ts.method = "paper": the stopping conditions as printed, (3.27) the move of the whole
  // configuration relative to its size |X^r| (positions from the box's corner, so it needs
  // DahaProblem::start) and (3.28) the overlaps alone. Otherwise (3.27) is the largest move
  // of one variable and (3.28) also asks a constraint with a multiplier to touch.
  bool printed_stopping = false;
};

// The DAHA defaults of a cluster model. The per-sphere models have a set of their own,
// tuned on smaller rigid problems: their answers depend on where a minimisation stops (the
// non-rigid attraction (3.5) has no minimum short of a collapsed cluster), and the rigid
// model's set makes their clusters more compact, further from the event-driven ones
// (docs/validation.md).
inline DahaParameters default_daha(TsModel model) {
  DahaParameters p;
  if (model == TsModel::rigid) return p;
  p.alpha = 0.043;
  p.gamma = 0.156;
  p.delta = 2.4;
  p.c_min = p.c_max = 0.229;
  p.beta_bar = 0.149;
  p.beta_max = 0.112;
  p.lambda0 = 0.10;
  p.stall_iterations = 440;
  return p;
}

// The paper's method: (3.29) active. The paper gives no value for c-bar and beta-bar
// (§4.1: "not reported here for brevity"); ours are chosen so that the dynamical values
// sit near the per-sphere models' tuned constants at a typical overlap (docs/time_stepping.md,
// "The paper's method as printed"). c_i is kept in [0, 1]: a damping factor 1 - c_i below
// zero would reverse the velocity. beta keeps the cap beta_max: the printed
// beta-bar sqrt(N) / phi_A is infinite once nothing overlaps.
inline constexpr double kPaperCBar = 0.229;
inline constexpr double kPaperBetaBar = 0.002;

// The DAHA parameters of ts.method = "paper" for a per-sphere model: that model's
// constants, (3.29) switched on with the constants above, no stall rule (a step the paper
// does not have), the stopping conditions as printed.
inline DahaParameters paper_daha(TsModel model) {
  DahaParameters p = default_daha(model);
  p.c_bar = kPaperCBar;
  p.c_min = 0.0;
  p.c_max = 1.0;
  p.beta_bar = kPaperBetaBar;
  p.stall_iterations = 0;
  p.printed_stopping = true;
  return p;
}

struct TimeSteppingSettings {
  TsMethod method = TsMethod::ours;
  TsModel model = TsModel::rigid;
  TsDtRule dt_rule = TsDtRule::growth;
  double dt_factor = 0.01;
  double dt_growth = 2.0;
  // Range Delta_W of the local attraction (3.30), a length; default 4 <R> as in the paper.
  std::optional<double> delta_w;
  // Almost-rigid: a link (adhesive bond) may stretch to (1 + bond_stretch) (R_i + R_j) and
  // no further; what keeps an old cluster from drifting apart.
  double bond_stretch = 0.1;
  int max_link_rounds = 50;    // repetitions of (3.1)-(3.2) within one step before giving up
  // Rigid model: a group goes to the fall-back at once, without a minimisation, when it
  // has at least retreat_pairs pairs of S (clusters flown deep into each other) or when a
  // pair of S overlaps by at least retreat_overlap (1 - d / (R_i + R_j): a sphere flew
  // through another). Such minimisations seldom converge and would cost most of a large
  // run (docs/time_stepping.md). The overlap rule is off by default (1: only centres that
  // coincide): at the paper's sizes the DAHA does solve such pairs, and the rule would
  // change the paper's method there.
  double retreat_overlap = 1.0;
  int retreat_pairs = 16;
  TsFallBack fall_back = TsFallBack::keep_flight;
  // keep-flight: the sweep's searches look this many sphere radii (the largest radius)
  // wider than a contact and search again from the pairs they met while a flight stays
  // that close to the one searched (flight_sweep.cpp). Speed only: any value >= 0 gives the
  // same run to the bit; 0 searches the cell list after every change of a flight.
  double sweep_reuse_margin = 0.5;
  DahaParameters daha;
};

std::string_view to_string(TsModel m);
std::string_view to_string(TsDtRule r);
std::string_view to_string(TsFallBack f);
std::string_view to_string(TsMethod m);

}  // namespace ballagg
