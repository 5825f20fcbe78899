#pragma once
// The geometry a state read from a file must have before a run starts from it: no two
// spheres of one cluster overlap by more than the overlap tolerance, and the spheres of
// each cluster form one contact graph (pairs touching within the contact tolerance,
// minimum images in a periodic box). The tolerances are those `ballagg verify` applies to
// a run of the same configuration (docs/verify.md), so that a run never starts from a
// state its own verification rejects. Spheres of different clusters are checked by
// assemble_state (they collide, whatever the engine: kInputOverlap).
#include <optional>

#include "ballagg/config/config.hpp"
#include "ballagg/core/box.hpp"
#include "ballagg/core/sphere_table.hpp"

namespace ballagg {

// Relative to the contact distance sigma = R_i + R_j of each pair.
struct LayoutTolerance {
  double overlap = 0.0;           // glued spheres: (sigma - d) / sigma at most this
  std::optional<double> contact;  // touching: d <= sigma (1 + contact); none: not checked
};

// Event-driven and rigid-body engines: exact contacts (kInputOverlap, kContact). ts: its
// clusters overlap internally by up to ts.eps_c; their links may open by ts.bond_stretch
// (almost-rigid), or without bound (non-rigid: connectivity is not checked).
LayoutTolerance layout_tolerance(const Config& config);

// Throws InputError naming the file lines of the two spheres concerned (the first such
// pair in file order, whatever the number of threads). O(N) on a cell list.
template <int D>
void check_sphere_layout(const Box<D>& box, const SphereTable<D>& table, const LayoutTolerance& tolerance);

}  // namespace ballagg
