#pragma once
// The free-flight step Delta t^n of the time-stepping engine (paper §3.1, §4.1).
//
// growth (Table 1): Delta t(0) = dt_factor L / max_i |V_i|, growing to dt_growth Delta t(0)
//   when one cluster is left. The paper does not give the law; ours is geometric in the
//   number of clusters M out of N: Delta t = Delta t(0) g^(1 - ln M / ln N), the same factor
//   for every decade of cluster count, so the step grows steadily over the whole run
//   rather than all at once during the early, fast merging.
// adaptive (3.3): Delta t = R_max / max_k |V_Ck|, recomputed at every step, so no cluster
//   moves more than one radius per step.
#include <algorithm>
#include <cmath>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/state.hpp"
#include "ballagg/engines/time_stepping/ts_settings.hpp"

namespace ballagg {

template <int D>
double max_cluster_speed(const State<D>& s) {
  double v2 = 0.0;
  for (int c : s.alive_clusters()) v2 = std::max(v2, s.clusters[c].velocity.squaredNorm());
  return std::sqrt(v2);
}

class TimeStepRule {
 public:
  template <int D>
  TimeStepRule(const TimeSteppingSettings& ts, const State<D>& s)
      : rule_(ts.dt_rule), growth_(ts.dt_growth), initial_clusters_(s.n_clusters()),
        radius_(s.max_radius()) {
    const double v = max_cluster_speed(s);
    initial_step_ = v > 0.0 ? ts.dt_factor * s.box.length / v : 0.0;
  }

  // The step for the current state; 0 when nothing moves.
  template <int D>
  double next(const State<D>& s) const {
    if (rule_ == TsDtRule::adaptive) {
      const double v = max_cluster_speed(s);
      return v > 0.0 ? radius_ / v : 0.0;
    }
    if (initial_clusters_ <= 1) return initial_step_ * growth_;
    const double progress = 1.0 - std::log(static_cast<double>(s.n_clusters())) / std::log(static_cast<double>(initial_clusters_));
    return initial_step_ * std::pow(growth_, std::clamp(progress, 0.0, 1.0));
  }

  double initial_step() const { return initial_step_; }

  // Checkpoints: the reference values taken from the state the run started from.
  void save(ByteWriter& w) const {
    w.put(initial_clusters_);
    w.put(initial_step_);
  }
  void restore(ByteReader& r) {
    initial_clusters_ = r.get<int>("initial cluster count");
    initial_step_ = r.get<double>("initial time step");
    if (initial_clusters_ < 1) r.fail("initial cluster count below 1");
    // Zero only for a state at rest (no cluster moves, nothing to step).
    if (!(std::isfinite(initial_step_) && initial_step_ >= 0.0)) r.fail("initial time step not a finite number >= 0");
  }

 private:
  TsDtRule rule_;
  double growth_;
  int initial_clusters_;
  double radius_;
  double initial_step_ = 0.0;
};

}  // namespace ballagg
