#pragma once
// Spheres of radii drawn from system.radius_distribution (or given a density), placed on
// the lattice or at random without overlaps, with their masses (docs/configuration.md,
// "Polydisperse spheres").
#include "ballagg/config/config.hpp"
#include "ballagg/core/sphere_table.hpp"

namespace ballagg {

// Random placement gives up on a sphere after this many rejected tries: the start is then
// refused (one error naming the volume fraction), never searched for longer.
inline constexpr int kMaxRandomPlacementTries = 100000;

// Positions, radii and masses of the generated start (velocities are left empty).
// Lattice: the sites of the monodisperse lattice, one sampled radius per site in the order
// drawn, refused unless the spacing exceeds the largest sampled diameter. Random: largest
// sphere first, each at a uniform point that overlaps no sphere placed before. Spheres are
// numbered along a Z-order curve. Throws InputError when the spheres cannot be placed.
template <int D>
SphereTable<D> sized_spheres(const Config& c, const Box<D>& box);

}  // namespace ballagg
