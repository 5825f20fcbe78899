#include "ballagg/config/lattice_spacing.hpp"

#include <fmt/format.h>

#include "ballagg/config/value_ranges.hpp"

namespace ballagg {

void read_lattice_spacing(SectionReader& ini, InitialConfig& initial) {
  initial.lattice_spacing = ini.real("lattice_spacing", positive, "must be a number > 0 (a length)");
  refuse_outside(ini, "lattice_spacing", initial.lattice_spacing, 0.0, range::kMaxBoxLength,
                 fmt::format("must be at most {:g} (the longest box allowed)", range::kMaxBoxLength));
}

void check_lattice_spacing(const Config& c, SectionReader& ini) {
  if (!c.initial.lattice_spacing) return;
  const double spacing = *c.initial.lattice_spacing;
  if (c.initial.positions != InitialPositions::lattice)
    ini.refuse("lattice_spacing", fmt::format("is read only with initial.positions = \"lattice\" (it is \"{}\")",
                                              to_string(c.initial.positions)));
  const char* other_box_key = c.system.volume_fraction ? "volume_fraction" : c.system.box_length ? "box_length" : nullptr;
  if (other_box_key)
    ini.refuse("lattice_spacing", fmt::format("sets the box (L = sites per side x spacing): give it or system.{}, "
                                              "not both", other_box_key));
  const std::int64_t side = lattice_side(c.system.n, c.system.dimension);
  const double box = static_cast<double>(side) * spacing;
  const bool one_radius = !polydisperse(c.system);
  // A law's largest radius is checked where the spheres are placed (polydisperse_start.cpp).
  if (one_radius && spacing <= 2.0 * c.system.radius)
    ini.refuse("lattice_spacing", fmt::format("must be larger than the diameter 2 system.radius = {}: neighbouring "
                                              "spheres of the lattice would touch", 2.0 * c.system.radius));
  const double smallest = one_radius ? c.system.radius : summarize_sampled_radii(c).smallest;
  if (box > range::kMaxBoxToRadius * smallest)
    ini.refuse("lattice_spacing", fmt::format("makes the box {} x {} = {:.6g} long, more than {:g} times the {} "
                                              "{:.6g}: positions at that box's scale cannot resolve a contact",
                                              side, spacing, box, range::kMaxBoxToRadius,
                                              one_radius ? "radius" : "smallest sampled radius", smallest));
}

}  // namespace ballagg
