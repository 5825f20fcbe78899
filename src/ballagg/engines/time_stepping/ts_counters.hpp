#pragma once
// The counters of the time-stepping engine, beyond those every engine keeps (steps among
// them).
#include <cstdint>

#include "ballagg/engines/engine_counters.hpp"

namespace ballagg {

struct TimeSteppingCounters : EngineCounters {
  std::int64_t minimisations = 0;      // DAHA solves (one per connected group per round)
  std::int64_t daha_iterations = 0;
  std::int64_t placed_at_contact = 0;  // groups not converged in max_iterations, placed at first contact
  std::int64_t link_rounds = 0;        // repetitions of (3.1)-(3.2) beyond the first
  std::int64_t rounds_exhausted = 0;   // steps that reached max_link_rounds
  double max_residual_overlap = 0.0;   // largest relative overlap left after any step
  double max_link_stretch = 0.0;       // largest d / (R_i + R_j) - 1 of an old link after a step
  // ts.method = "paper": minimisations that reached max_iterations without meeting
  // (3.27)-(3.28), whose iterate the step took as it was. Saved and reported by that method
  // alone (`paper`), so that the checkpoints and summaries of the other stay as they were.
  std::int64_t minimisations_unconverged = 0;

  void save(ByteWriter& w, bool paper = false) const {
    EngineCounters::save(w);
    for (std::int64_t v : {minimisations, daha_iterations, placed_at_contact, link_rounds, rounds_exhausted}) w.put(v);
    w.put(max_residual_overlap);
    w.put(max_link_stretch);
    if (paper) w.put(minimisations_unconverged);
  }
  void restore(ByteReader& r, bool paper = false) {
    EngineCounters::restore(r);
    for (std::int64_t* v : {&minimisations, &daha_iterations, &placed_at_contact, &link_rounds, &rounds_exhausted})
      *v = r.get<std::int64_t>("counters");
    max_residual_overlap = r.get<double>("counters");
    max_link_stretch = r.get<double>("counters");
    if (paper) minimisations_unconverged = r.get<std::int64_t>("counters");
  }
  // with_links: the cluster models whose old clusters hold by links that can stretch;
  // paper: ts.method = "paper", which has no fall-back and counts what did not converge.
  EngineCounts report(bool with_links, bool paper = false) const {
    EngineCounts counts{{"steps", steps}, {"minimisations", minimisations}, {"daha_iterations", daha_iterations}};
    if (paper) counts.push_back({"minimisations_unconverged", minimisations_unconverged});
    else counts.push_back({"placed_at_contact", placed_at_contact});
    counts.push_back({"link_rounds", link_rounds});
    counts.push_back({"link_rounds_exhausted", rounds_exhausted});
    counts.push_back({"max_residual_overlap", max_residual_overlap});
    if (with_links) counts.push_back({"max_link_stretch", max_link_stretch});
    return counts;
  }
};

}  // namespace ballagg
