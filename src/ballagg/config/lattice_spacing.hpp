#pragma once
// initial.lattice_spacing: the square or cubic lattice of a generated start at a given
// spacing, which then sets the box (L = sites per side x spacing) whatever the radius, as
// in Degond et al. 2023, App. A (unit spacing, R = 0.2); and its rules against the other keys.
#include "ballagg/config/config.hpp"
#include "ballagg/config/section_reader.hpp"

namespace ballagg {

// Reads the key (a length > 0, at most range::kMaxBoxLength) into `initial`.
void read_lattice_spacing(SectionReader& ini, InitialConfig& initial);

// Refuses initial.lattice_spacing (one line naming it, its file line or --set, and what
// is allowed) with a start other than the lattice, with system.volume_fraction or
// system.box_length (each of which sets the box too), at most a sphere's diameter (the
// spheres would touch), or making the box longer than range::kMaxBoxToRadius times the
// (smallest sampled) radius. Call before the default volume fraction is set.
void check_lattice_spacing(const Config& c, SectionReader& ini);

}  // namespace ballagg
