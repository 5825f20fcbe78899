#pragma once
// The trajectory part of `ballagg verify` (docs/verify.md, "Trajectories"): that each
// trajectory file in a run directory belongs to the run of its config.toml. Its frames
// must come in time order, none repeated, at the times the run's output.snapshot_every
// puts them (the initial state at t = 0, frame k at k * snapshot_every, the last at the
// run's final time), each with the run's number of spheres, box and dimension. A file the
// configuration does not write at all is another run's. These catch a trajectory spliced
// from two runs or written twice over.
#include <string>

#include "ballagg/run/run_directory.hpp"
#include "ballagg/run/verify_run.hpp"

namespace ballagg {

// `spheres`: the run's number of spheres (final.csv), 0 when it may change during the
// run (coalescing spheres); `largest_radius` of final.csv (the depth of a 2D XYZ cell).
template <int D>
void verify_trajectories(const RunDirectory& run, double final_time, int spheres, double largest_radius,
                         Verification& out);

}  // namespace ballagg
