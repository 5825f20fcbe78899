#include "ballagg/initial/initial_state.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <optional>
#include <span>

#include <fmt/format.h>

#include "ballagg/core/random.hpp"
#include "ballagg/core/tolerances.hpp"
#include "ballagg/initial/cluster_groups.hpp"
#include "ballagg/initial/lattice_sites.hpp"
#include "ballagg/initial/polydisperse_start.hpp"
#include "ballagg/initial/space_filling_curve.hpp"
#include "ballagg/initial/sphere_layout_check.hpp"
#include "ballagg/initial/state_ranges.hpp"
#include "ballagg/io/state_csv.hpp"
#include "ballagg/spatial/cell_grid.hpp"

namespace ballagg {
namespace {

// Random sequential addition gives up on a sphere after this many rejected tries.
constexpr int kMaxPlacementTries = 100000;

// Where the keys that decide whether generated spheres fit came from (the --set
// arguments among them, or the configuration file), for the message when they do not.
std::string placement_origin(const Config& c) {
  return origin_of(c, {"system.dimension", "system.n", "system.volume_fraction", "system.box_length", "system.radius",
                       "system.boundary", "initial.positions", "initial.lattice_spacing"});
}

std::string fmt_vec(const auto& v) {
  std::string s = "(";
  for (int a = 0; a < v.size(); ++a) s += fmt::format("{}{}", a ? ", " : "", v[a]);
  return s + ")";
}

std::string where(const auto& table, int sphere) {
  if (table.line.empty()) return fmt::format("sphere {}", sphere);
  return fmt::format("{}:{}", table.source, table.line[sphere]);
}

// Generated spheres are numbered along a Z-order curve (space_filling_curve.hpp).
template <int D>
void number_along_space_filling_curve(std::vector<Vec<D>>& x, const Box<D>& box) {
  std::vector<Vec<D>> sorted;
  sorted.reserve(x.size());
  for (std::size_t i : z_order<D>(x, box)) sorted.push_back(x[i]);
  x.swap(sorted);
}

template <int D>
std::vector<Vec<D>> lattice_positions(const Config& c, const Box<D>& box) {
  const std::int64_t n = c.system.n;
  const std::int64_t side = lattice_side(n, D);
  const double spacing = lattice_spacing(c, box);
  if (spacing <= 2.0 * c.system.radius) {
    const double max_vf = (D == 2 ? std::numbers::pi / 4.0 : std::numbers::pi / 6.0) *
                          static_cast<double>(n) / std::pow(side, D);
    throw InputError(fmt::format(
        "{}: initial.positions = \"lattice\": {} spheres need a {}-per-side lattice whose spacing {:.6g} is not larger "
        "than the diameter {:.6g}; lower system.volume_fraction below {:.4f} (or the radius), or enlarge the box",
        placement_origin(c), n, side, spacing, 2.0 * c.system.radius, max_vf));
  }
  std::vector<Vec<D>> x = lattice_sites<D>(n, side, spacing);
  number_along_space_filling_curve(x, box);
  return x;
}

template <int D>
std::vector<Vec<D>> random_positions(const Config& c, const Box<D>& box) {
  const std::int64_t n = c.system.n;
  const double r = c.system.radius;
  if (!box.periodic() && box.length <= 2.0 * r)
    throw InputError(fmt::format("{}: the box length {:.6g} is not larger than a sphere's diameter {:.6g}",
                                 placement_origin(c),
                                 box.length, 2.0 * r));
  Random rng(c.initial.seed, RandomPurpose::positions);
  CellGrid<D> grid(box, 2.0 * r, static_cast<int>(n));
  std::vector<Vec<D>> x;
  x.reserve(n);
  const double lo = box.periodic() ? 0.0 : r, hi = box.periodic() ? box.length : box.length - r;
  for (std::int64_t k = 0; k < n; ++k) {
    int tries = 0;
    while (true) {
      Vec<D> p;
      for (int a = 0; a < D; ++a) p[a] = box.wrap(rng.uniform(lo, hi));
      bool free = true;
      grid.for_each_near(p, [&](int, const Vec<D>& xj) { free = free && box.separation(p, xj).norm() > 2.0 * r; });
      if (free) {
        grid.insert(static_cast<int>(k), p);
        x.push_back(p);
        break;
      }
      if (++tries == kMaxPlacementTries) {
        throw InputError(fmt::format(
            "{}: initial.positions = \"random\": sphere {} of {} found no free place in {} tries; the volume fraction "
            "is too high for random placement (random sequential addition jams near {}), use initial.positions = "
            "\"lattice\" or a lower system.volume_fraction",
            placement_origin(c), k + 1, n, kMaxPlacementTries, D == 2 ? "0.547 in 2D" : "0.38 in 3D"));
      }
    }
  }
  number_along_space_filling_curve(x, box);
  return x;
}

template <int D>
std::vector<Vec<D>> random_velocities(const Config& c, std::int64_t n) {
  Random rng(c.initial.seed, RandomPurpose::velocities);
  std::vector<Vec<D>> v(n);
  const double speed = c.initial.speed;
  for (Vec<D>& vi : v) {
    switch (c.initial.velocities) {
      case InitialVelocities::fixed_speed:  // eq. (4.2): given speed, uniform direction
        vi = speed * rng.unit_vector<D>();
        break;
      case InitialVelocities::uniform:  // App. A: each component uniform in [-1/2, 1/2], times speed
        for (int a = 0; a < D; ++a) vi[a] = speed * (rng.uniform() - 0.5);
        break;
      case InitialVelocities::gaussian:  // Maxwellian with mean square speed = speed^2
        for (int a = 0; a < D; ++a) vi[a] = speed / std::sqrt(static_cast<double>(D)) * rng.normal();
        break;
    }
  }
  return v;
}

// Offsets of glued spheres relative to their cluster's first sphere. With periodic faces a
// cluster may straddle the box, so it is unwrapped along chains of near spheres (closer
// than twice their contact distance), where the minimum image is the true separation.
template <int D>
std::vector<Vec<D>> unwrapped_offsets(const Box<D>& box, const SphereTable<D>& t, const ClusterGroups& groups,
                                      const CellGrid<D>& grid) {
  const int n = static_cast<int>(t.radius.size());
  std::vector<Vec<D>> offset(n, Vec<D>::Zero());
  std::vector<char> placed(n, 0);
  for (int c = 0; c < groups.size(); ++c) {
    const std::span<const std::int32_t> group = groups.members(c);
    const int root = group.front();
    placed[root] = 1;
    std::deque<int> queue{root};
    while (!queue.empty()) {
      const int s = queue.front();
      queue.pop_front();
      grid.for_each_near(t.position[s], [&](int j, const Vec<D>&) {
        if (placed[j] || groups.label(j) != groups.label(s)) return;
        const Vec<D> d = box.separation(t.position[j], t.position[s]);
        if (d.norm() >= 2.0 * (t.radius[s] + t.radius[j]) || d.norm() >= 0.5 * box.length) return;
        offset[j] = offset[s] + d;
        placed[j] = 1;
        queue.push_back(j);
      });
    }
    for (int j : group)
      if (!placed[j]) offset[j] = box.separation(t.position[j], t.position[root]);
  }
  return offset;
}

// Turns the table's positions into body-frame positions with every cluster's reference
// point at the origin: each sphere where the file puts it, except that spheres of a
// cluster straddling a periodic face are moved by whole box lengths to sit next to their
// neighbours. Keeping the file's numbers wherever possible makes a state written by
// ballagg read back bit for bit. `offset` is empty when every sphere is a cluster of its
// own (all offsets zero).
template <int D>
void to_body_positions(const Box<D>& box, std::vector<Vec<D>>& position, const ClusterGroups& groups,
                       const std::vector<Vec<D>>& offset) {
  if (!box.periodic()) return;
  const double l = box.length;
  const auto offset_of = [&](int j, int a) { return offset.empty() ? 0.0 : offset[j][a]; };
  for (int c = 0; c < groups.size(); ++c) {
    const std::span<const std::int32_t> group = groups.members(c);
    for (int a = 0; a < D; ++a) {
      // Read before the loop below moves the root itself.
      const double root = position[group.front()][a];
      // Whole periods that bring the cluster's lowest coordinate into [-L/2, L/2).
      double lowest = std::numeric_limits<double>::infinity();
      for (int j : group) lowest = std::min(lowest, root + offset_of(j, a));
      const double shift = -l * std::floor(lowest / l + 0.5);
      for (int j : group) {
        const double unwrapped = root + offset_of(j, a) + shift;
        const double periods = std::nearbyint((unwrapped - position[j][a]) / l);
        if (periods != 0.0) position[j][a] += periods * l;
      }
    }
  }
}

// The rigid-body engine follows every body's centre of mass on its unwrapped trajectory,
// from wherever the state puts it (assemble_state picks, cluster by cluster, the image whose
// lowest point lies in [-L/2, L/2)). Moving each body by whole box lengths so that its
// centre of mass lies in the box makes these trajectories one picture of the system:
// bodies that meet inside the box meet there in the engine's coordinates too, and the
// orbital angular momentum about the box centre is that of the state as the file gives it
// (docs/rigid_body.md). Folded positions are unchanged.
template <int D>
void put_centres_of_mass_in_box(State<D>& s) {
  if (!s.box.periodic()) return;
  const double l = s.box.length;
  for (int c : s.alive_clusters()) {
    Cluster<D>& k = s.clusters[c];
    Vec<D> centre = Vec<D>::Zero();
    for (int i : k.members) centre += s.spheres.mass[i] * s.spheres.offset[i];
    centre = k.anchor + centre / k.mass;
    for (int a = 0; a < D; ++a) k.anchor[a] -= l * floor_to_integer(centre[a] / l);
  }
}

// Folds the spheres into a periodic box, or checks that they fit between the walls.
template <int D>
void put_spheres_in_box(const Box<D>& box, SphereTable<D>& t, double max_radius) {
  if (box.periodic() && box.length <= 4.0 * max_radius)
    throw InputError(fmt::format("system.box_length = {}: a periodic box must be longer than 4 times the largest "
                                 "radius ({}) so that each pair has one nearest image", box.length, max_radius));
  for (int i = 0; i < static_cast<int>(t.radius.size()); ++i) {
    if (box.periodic()) {
      t.position[i] = box.wrap(t.position[i]);
      continue;
    }
    const double slack = tolerance::kInputOverlap * 2.0 * t.radius[i];
    for (int a = 0; a < D; ++a) {
      if (t.position[i][a] - t.radius[i] < -slack || t.position[i][a] + t.radius[i] > box.length + slack)
        throw InputError(fmt::format("{}: the sphere at {} with radius {} does not fit in the box [0, {}] (walls)",
                                     where(t, i), fmt_vec(t.position[i]), t.radius[i], box.length));
    }
  }
}

template <int D>
void refuse_overlaps(const Box<D>& box, const SphereTable<D>& t, const CellGrid<D>& grid) {
  for (int i = 0; i < static_cast<int>(t.radius.size()); ++i) {
    grid.for_each_near(t.position[i], [&](int j, const Vec<D>&) {
      if (j <= i) return;
      // Spheres of one glued cluster never collide with each other: overlaps between
      // them (a time-stepping run leaves up to ts.eps_c) are harmless.
      if (!t.cluster.empty() && t.cluster[i] == t.cluster[j]) return;
      const double sigma = t.radius[i] + t.radius[j];
      const double d = box.separation(t.position[i], t.position[j]).norm();
      if (d < sigma * (1.0 - tolerance::kInputOverlap)) {
        const std::string other = t.line.empty() ? fmt::format("sphere {}", j) : fmt::format("the sphere of line {}", t.line[j]);
        throw InputError(fmt::format("{}: this sphere overlaps {} by {:.3g} of their contact distance (spheres must not "
                                     "overlap)", where(t, i), other, (sigma - d) / sigma));
      }
    });
  }
}

// Each cluster's members and velocity. Glued spheres written by ballagg share one velocity
// exactly: it is kept bit for bit. Others (equal within kGluedVelocity of the fastest
// sphere's speed) move with their mass-weighted mean.
template <int D>
void set_cluster_motions(State<D>& s, const SphereTable<D>& t, const ClusterGroups& groups) {
  double max_speed = 0.0;
  for (const Vec<D>& v : t.velocity) max_speed = std::max(max_speed, v.norm());
  s.clusters.resize(groups.size());
  for (int c = 0; c < groups.size(); ++c) {
    Cluster<D>& k = s.clusters[c];
    const std::span<const std::int32_t> members = groups.members(c);
    const int root = members.front();
    k.members.assign(members.data(), members.data() + members.size());
    k.anchor = Vec<D>::Zero();
    Vec<D> momentum = Vec<D>::Zero();
    double mass = 0.0;
    bool identical = true;
    for (int i : members) {
      momentum += t.mass[i] * t.velocity[i];
      mass += t.mass[i];
      identical = identical && t.velocity[i] == t.velocity[root];
    }
    k.velocity = identical ? t.velocity[root] : Vec<D>(momentum / mass);
    for (int i : members) {
      if ((t.velocity[i] - t.velocity[root]).norm() > tolerance::kGluedVelocity * max_speed) {
        throw InputError(fmt::format("{}: velocity {} differs from {} of the first sphere of its cluster ({}); "
                                     "spheres glued into one cluster must move together",
                                     where(t, i), fmt_vec(t.velocity[i]), fmt_vec(t.velocity[root]), where(t, root)));
      }
    }
  }
}

// Spin columns: each cluster spins as its first sphere says; the others must agree.
template <int D>
void set_cluster_spins(State<D>& s, const SphereTable<D>& t, const ClusterGroups& groups) {
  if (t.spin.empty()) return;
  double max_spin = 0.0;
  for (const Spin<D>& w : t.spin) max_spin = std::max(max_spin, w.norm());
  s.spin.resize(groups.size());
  for (int c = 0; c < groups.size(); ++c) {
    const std::span<const std::int32_t> members = groups.members(c);
    const int root = members.front();
    s.spin[c].angular_velocity = t.spin[root];
    for (int i : members)
      if ((t.spin[i] - t.spin[root]).norm() > tolerance::kGluedVelocity * max_spin)
        throw InputError(fmt::format("{}: spin {} differs from {} of the first sphere of its cluster ({}); "
                                     "spheres glued into one cluster must spin together",
                                     where(t, i), fmt_vec(t.spin[i]), fmt_vec(t.spin[root]), where(t, root)));
  }
}

// Which generated starts cannot overlap: a lattice whose spacing exceeds the largest
// diameter (lattice_positions and lattice_start refuse any other) has no overlapping pair,
// periodic images included, as the box holds a whole number of spacings per side.
enum class OverlapCheck { done, not_needed };

// The state from the spheres of t, which it consumes: their positions become the body
// frame offsets, their radii and masses the state's.
template <int D>
State<D> assemble_consuming(const Box<D>& box, SphereTable<D>& t, OverlapCheck overlaps) {
  const int n = static_cast<int>(t.radius.size());
  const double max_radius = t.radius.empty() ? 0.0 : *std::max_element(t.radius.begin(), t.radius.end());
  put_spheres_in_box(box, t, max_radius);
  const bool glued = !t.cluster.empty();
  std::optional<CellGrid<D>> grid;
  if (overlaps == OverlapCheck::done || glued) {
    grid.emplace(box, 2.0 * max_radius, n);
    for (int i = 0; i < n; ++i) grid->insert(i, t.position[i]);
  }
  if (overlaps == OverlapCheck::done) refuse_overlaps(box, t, *grid);

  ClusterGroups groups(t.cluster, n);
  std::vector<Vec<D>> offset;
  if (glued) offset = unwrapped_offsets(box, t, groups, *grid);
  grid.reset();
  to_body_positions(box, t.position, groups, offset);
  offset = {};
  State<D> s;
  s.box = box;
  set_cluster_motions(s, t, groups);
  set_cluster_spins(s, t, groups);
  t.velocity = {};
  s.spheres.offset = std::move(t.position);
  s.spheres.radius = std::move(t.radius);
  s.spheres.mass = std::move(t.mass);
  s.spheres.cluster = std::move(groups).take_labels();
  s.finalize();
  return s;
}

}  // namespace

template <int D>
State<D> assemble_state(const Box<D>& box, SphereTable<D>&& table) {
  return assemble_consuming(box, table, OverlapCheck::done);
}

template <int D>
State<D> assemble_state(const Box<D>& box, const SphereTable<D>& table) {
  SphereTable<D> copy = table;
  return assemble_consuming(box, copy, OverlapCheck::done);
}

namespace {

// The spheres generated from the configuration: on a lattice or at random, of one radius
// or drawn from system.radius_distribution.
template <int D>
SphereTable<D> generated_spheres(const Config& c, const Box<D>& box) {
  SphereTable<D> table;
  if (polydisperse(c.system)) {
    table = sized_spheres<D>(c, box);
  } else {
    table.position = c.initial.positions == InitialPositions::lattice ? lattice_positions<D>(c, box)
                                                                      : random_positions<D>(c, box);
    table.radius.assign(c.system.n, c.system.radius);
    table.mass.assign(c.system.n, sphere_mass(c.system, c.system.radius));
  }
  table.velocity = random_velocities<D>(c, c.system.n);
  return table;
}

// Only the rigid-body engine rotates clusters: spins of a state file are refused for the
// others unless zero.
template <int D>
void keep_spins_for_rigid_bodies(State<D>& s, const SphereTable<D>& table, const Config& c) {
  if (c.engine.kind == EngineKind::rigid_body) return;
  for (std::size_t i = 0; i < table.spin.size(); ++i)
    if (table.spin[i] != Spin<D>::Zero())
      throw InputError(fmt::format("{}: the sphere spins ({}), but engine.kind = \"{}\" does not rotate clusters: "
                                   "use engine.kind = \"rigid-body\" or set the spin columns to 0",
                                   where(table, static_cast<int>(i)), fmt_vec(table.spin[i]), to_string(c.engine.kind)));
  s.spin.clear();
}

template <int D>
void subtract_mean_velocity(State<D>& s) {
  const Vec<D> mean = s.momentum() / s.total_mass();
  for (int k = 0; k < static_cast<int>(s.clusters.size()); ++k)
    if (s.clusters[k].alive()) s.set_velocity(k, s.clusters[k].velocity - mean, s.time);
}

// The state's positions are those at time t (initial.time): every cluster is anchored
// there, and the clock reads t.
template <int D>
void start_clock_at(State<D>& s, double t) {
  for (Cluster<D>& k : s.clusters) k.anchor_time = t;
  s.time = t;
}

// What every initial state gets once its spheres are assembled: spins only for the engine
// that rotates clusters, initial.zero_momentum, the rigid-body engine's centres of mass,
// and the clock at initial.time.
template <int D>
State<D> finish_initial_state(const Config& c, State<D> s, const SphereTable<D>& table) {
  keep_spins_for_rigid_bodies(s, table, c);
  if (c.initial.zero_momentum) subtract_mean_velocity(s);
  if (c.engine.kind == EngineKind::rigid_body) put_centres_of_mass_in_box(s);
  start_clock_at(s, c.initial.time);
  return s;
}

}  // namespace

template <int D>
State<D> make_initial_state(const Config& c) {
  if (c.initial.positions == InitialPositions::file) return state_from_spheres<D>(c, read_state_csv<D>(c.initial.file));
  const Box<D> box{resolved_box_length(c), c.system.boundary};
  SphereTable<D> table = generated_spheres<D>(c, box);
  const OverlapCheck overlaps =
      c.initial.positions == InitialPositions::lattice ? OverlapCheck::not_needed : OverlapCheck::done;
  // The table keeps what finish_initial_state reads (spins, file lines) once consumed.
  State<D> s = assemble_consuming(box, table, overlaps);
  return finish_initial_state(c, std::move(s), table);
}

template <int D>
State<D> state_from_spheres(const Config& c, const SphereTable<D>& table) {
  Box<D> box{resolved_box_length(c), c.system.boundary};
  check_state_ranges(table, box, c);
  State<D> s = assemble_state(box, table);
  check_sphere_layout(box, table, layout_tolerance(c));
  return finish_initial_state(c, std::move(s), table);
}

template State<2> make_initial_state<2>(const Config&);
template State<2> state_from_spheres<2>(const Config&, const SphereTable<2>&);
template State<3> state_from_spheres<3>(const Config&, const SphereTable<3>&);
template State<3> make_initial_state<3>(const Config&);
template State<2> assemble_state<2>(const Box<2>&, const SphereTable<2>&);
template State<3> assemble_state<3>(const Box<3>&, const SphereTable<3>&);
template State<2> assemble_state<2>(const Box<2>&, SphereTable<2>&&);
template State<3> assemble_state<3>(const Box<3>&, SphereTable<3>&&);

}  // namespace ballagg
