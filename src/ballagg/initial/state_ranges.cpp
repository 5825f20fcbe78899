#include "ballagg/initial/state_ranges.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "ballagg/config/value_ranges.hpp"

namespace ballagg {
namespace {

template <int D>
std::string row(const SphereTable<D>& t, int i) {
  if (t.line.empty()) return fmt::format("sphere {}", i);
  return fmt::format("{}:{}", t.source, t.line[i]);
}

template <int D>
std::string velocity_columns() {
  return D == 2 ? "vx,vy" : "vx,vy,vz";
}

template <int D>
std::string spin_columns() {
  return D == 2 ? "wz" : "wx,wy,wz";
}

// Where a value of row i is: "FILE:LINE: column radius" in a state file; "radii[i]" in
// the arrays a state is built from in Python (a table without file lines).
template <int D>
std::string value_at(const SphereTable<D>& t, int i, std::string_view columns, std::string_view array) {
  if (t.line.empty()) return fmt::format("{}[{}]", array, i);
  return fmt::format("{}: {}", row(t, i), columns);
}

// One row: each value within its own range.
template <int D>
void check_row(const SphereTable<D>& t, int i, const Box<D>& box) {
  const double radius = t.radius[i], mass = t.mass[i];
  if (radius < range::kMinRadius || radius > range::kMaxRadius)
    throw InputError(fmt::format("{}: {} is outside [{}, {}] (choose units in which radii are near 1)",
                                 value_at(t, i, "column radius", "radii"), radius, range::kMinRadius, range::kMaxRadius));
  if (mass < range::kMinMass || mass > range::kMaxMass)
    throw InputError(fmt::format("{}: {} is outside [{}, {}] (choose units in which masses are near 1)",
                                 value_at(t, i, "column mass", "masses"), mass, range::kMinMass, range::kMaxMass));
  const double speed = t.velocity[i].stableNorm();  // no overflow of the squares
  if (speed > range::kMaxSpeed)
    throw InputError(fmt::format("{}: the speed {:.6g} is above {} (choose units in which speeds are near 1)",
                                 value_at(t, i, "columns " + velocity_columns<D>(), "velocities"), speed,
                                 range::kMaxSpeed));
  if (!t.spin.empty() && t.spin[i].stableNorm() * radius > range::kMaxSpeed)
    throw InputError(fmt::format("{}: the spin {:.6g} times the radius {} is a speed above {}",
                                 value_at(t, i, "columns " + spin_columns<D>(), "angular_velocities"),
                                 t.spin[i].stableNorm(), radius, range::kMaxSpeed));
  if (!box.periodic()) return;  // walls: assemble_state checks that every sphere fits
  static constexpr const char* axes[] = {"x", "y", "z"};
  const double reach = range::kMaxPeriodicOverhang * box.length;
  for (int a = 0; a < D; ++a) {
    if (t.position[i][a] >= -reach && t.position[i][a] <= box.length + reach) continue;
    const std::string where = t.line.empty() ? fmt::format("positions[{}, {}]", i, a)
                                             : fmt::format("{}: column {}", row(t, i), axes[a]);
    throw InputError(fmt::format("{}: {} is more than {} box length outside [0, {}] (periodic box: fold the "
                                 "coordinates into the box)",
                                 where, t.position[i][a], range::kMaxPeriodicOverhang, box.length));
  }
}

}  // namespace

template <int D>
void check_state_ranges(const SphereTable<D>& t, const Box<D>& box, const Config& c) {
  const int n = static_cast<int>(t.radius.size());
  int smallest = 0;
  for (int i = 0; i < n; ++i) {
    check_row(t, i, box);
    if (t.radius[i] < t.radius[smallest]) smallest = i;
  }
  if (n == 0) return;
  const double r = t.radius[smallest];
  if (box.length > range::kMaxBoxToRadius * r)
    throw InputError(fmt::format("{}: system.box_length = {} is more than {:g} times the smallest radius {} ({}): "
                                 "positions at that box's scale cannot resolve a contact",
                                 origin_of(c, {"system.box_length", "initial.file"}), box.length, range::kMaxBoxToRadius,
                                 r, row(t, smallest)));
  if (c.engine.skin) {
    const double lo = range::kMinSkinToRadius * r, hi = range::kMaxSkinToBox * box.length;
    if (*c.engine.skin < lo || *c.engine.skin > hi)
      throw InputError(fmt::format("{}: engine.skin = {}: must be from {} to {} ({:g} times the smallest radius, of {}, "
                                   "to {} box lengths)", origin_of(c, {"engine.skin", "initial.file"}),
                                   *c.engine.skin, lo, hi, range::kMinSkinToRadius,
                                   row(t, smallest), range::kMaxSkinToBox));
  }
}

template <int D>
void check_resolved_ranges(const Config& c, const State<D>& s) {
  const bool listed = c.engine.kind == EngineKind::ed || c.engine.kind == EngineKind::rigid_body;  // engines with a skin
  if (!listed || !c.engine.skin || !s.box.periodic()) return;
  // The engines shorten the skin so that every listed pair stays closer than half a
  // periodic box (choose_skin of the ed and rigid-body engines).
  const double room = 0.99 * (0.5 * s.box.length - 2.0 * s.max_radius()) / 1.5;
  const double smallest = *std::min_element(s.spheres.radius.begin(), s.spheres.radius.end());
  const double lo = range::kMinSkinToRadius * smallest;
  if (std::min(*c.engine.skin, room) >= lo) return;
  throw InputError(fmt::format("{}: system.box_length = {}: a periodic box must be longer than 4 times the largest "
                               "radius ({}) by enough for a neighbour-list skin of {:g} times the smallest radius: at "
                               "least {}",
                               origin_of(c, {"system.box_length", "system.volume_fraction", "system.n", "system.radius",
                                             "initial.file", "engine.skin"}),
                               s.box.length, s.max_radius(), range::kMinSkinToRadius,
                               4.0 * s.max_radius() + 3.0 * lo / 0.99 * (1.0 + 1e-9)));
}

template void check_state_ranges<2>(const SphereTable<2>&, const Box<2>&, const Config&);
template void check_state_ranges<3>(const SphereTable<3>&, const Box<3>&, const Config&);
template void check_resolved_ranges<2>(const Config&, const State<2>&);
template void check_resolved_ranges<3>(const Config&, const State<3>&);

}  // namespace ballagg
