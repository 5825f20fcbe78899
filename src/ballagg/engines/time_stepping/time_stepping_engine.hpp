#pragma once
// The time-stepping engine (`ts`, paper §3): free flight of every cluster for a step
// Delta t, walls, overlap detection on a cell list, then the iterative minimisation
// (3.1)-(3.2) with the damped Arrow–Hurwicz algorithm over the adhesive links, and the
// velocities of the new clusters by rule (2.9). docs/time_stepping.md describes it.
#include <memory>

#include "ballagg/engines/engine.hpp"
#include "ballagg/engines/time_stepping/daha.hpp"
#include "ballagg/engines/time_stepping/ts_settings.hpp"

namespace ballagg {

// With a sink, every minimisation problem is handed to it before it is solved (tuning).
template <int D>
std::unique_ptr<Engine<D>> make_time_stepping_engine(const TimeSteppingSettings& settings,
                                                     DahaProblemSink<D>* sink = nullptr);

}  // namespace ballagg
