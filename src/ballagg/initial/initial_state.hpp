#pragma once
// The state at t = 0 from a configuration: spheres placed on a lattice (paper §4.1), at
// random without overlaps, or read from a file; velocities drawn from the chosen law.
#include "ballagg/config/config.hpp"
#include "ballagg/core/sphere_table.hpp"
#include "ballagg/core/state.hpp"

namespace ballagg {

// Throws InputError when the configuration cannot be realised (spheres that do not fit,
// overlaps or bad clusters in an input file).
template <int D>
State<D> make_initial_state(const Config& config);

// The state at t = 0 from given spheres in the configuration's box, checked as a state file
// (initial.file) is: value ranges, overlaps, glued clusters that touch and move together,
// spins; then initial.zero_momentum. A table without file lines (Python's arrays) names a
// sphere by its index in the arrays.
template <int D>
State<D> state_from_spheres(const Config& config, const SphereTable<D>& table);

// Builds a state from explicit spheres (positions are folded into a periodic box; spheres
// with equal table.cluster values are glued into rigid clusters). Checks that spheres fit
// in the box, do not overlap, and that glued spheres share a velocity. The second form
// consumes the table: its positions, radii and masses move into the state (its velocities
// are released), which saves a copy of them.
template <int D>
State<D> assemble_state(const Box<D>& box, const SphereTable<D>& table);
template <int D>
State<D> assemble_state(const Box<D>& box, SphereTable<D>&& table);

}  // namespace ballagg
