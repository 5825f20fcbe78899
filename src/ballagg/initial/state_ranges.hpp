#pragma once
// The numeric ranges of config/value_ranges.hpp applied to what only a state brings: the
// rows of a state file (radii, masses, speeds, spins, positions, and the box and skin
// against the file's smallest radius), and the values resolved from the state (the
// neighbour-list skin as a periodic box leaves room for it).
#include "ballagg/config/config.hpp"
#include "ballagg/core/sphere_table.hpp"
#include "ballagg/core/state.hpp"

namespace ballagg {

// Throws InputError naming the file line and column (or the key) of the first value
// outside its range. Called on a state file's table before anything is built from it.
template <int D>
void check_state_ranges(const SphereTable<D>& table, const Box<D>& box, const Config& config);

// Throws InputError when the configuration resolved for state s (its defaults filled in)
// leaves a neighbour-list skin below the resolution of positions.
template <int D>
void check_resolved_ranges(const Config& resolved, const State<D>& s);

}  // namespace ballagg
