#pragma once
// What the solvers of a step's groups read of the step: the minimisation (solve_group),
// the retreat and the flight sweep (the fall-backs) and the order of the repairs. Built by
// the engine once per round, with named members (designated initialisers), and shared
// read-only by every group of the round, on every thread.
#include <vector>

#include "ballagg/core/run_guard.hpp"
#include "ballagg/core/state.hpp"
#include "ballagg/engines/time_stepping/adhesive_links.hpp"
#include "ballagg/engines/time_stepping/adhesive_set.hpp"
#include "ballagg/engines/time_stepping/daha.hpp"
#include "ballagg/engines/time_stepping/step_bodies.hpp"
#include "ballagg/engines/time_stepping/ts_settings.hpp"
#include "ballagg/spatial/movable_cell_list.hpp"

namespace ballagg {

template <int D>
struct StepView {
  const State<D>& state;
  const std::vector<Vec<D>>& positions;   // sphere centres now (folded into the box)
  const std::vector<Vec<D>>& step_shift;  // per sphere: how far this step's minimisations moved it
  const std::vector<Vec<D>>& flight;      // per cluster: how far this step's free flight moved it
  const StepBodies& bodies;               // the clusters of the step joined by its links
  const MovableCellList<D>& cells;        // every sphere, binned at most cell_slack from `positions`
  double cell_slack;
  const AdhesiveSet& S;                   // the adhesive set S of the round (3.1)-(3.2)
  const AdhesiveLinks& links;             // per-sphere models: the links of the old clusters
  const TimeSteppingSettings& settings;
  double length_scale;                    // mean contact distance 2 <R>
  double delta_w;                         // resolved Delta_W of (3.30)
  double mean_mass;
  DahaProblemSink<D>* sink = nullptr;     // sees every problem before it is solved (tuning)
  const RunGuard* guard = nullptr;        // the run's: cuts long minimisations short
};

}  // namespace ballagg
