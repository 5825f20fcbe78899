#include "ballagg/initial/polydisperse_start.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "ballagg/core/random.hpp"
#include "ballagg/initial/lattice_sites.hpp"
#include "ballagg/initial/space_filling_curve.hpp"
#include "ballagg/spatial/cell_grid.hpp"

namespace ballagg {
namespace {

template <int D>
std::vector<Vec<D>> lattice_start(const Config& c, const Box<D>& box, double largest) {
  const std::int64_t n = c.system.n;
  const std::int64_t side = lattice_side(n, D);
  const double spacing = lattice_spacing(c, box);
  if (spacing <= 2.0 * largest)
    throw InputError(fmt::format(
        "{}: initial.positions = \"lattice\": {} spheres need a {}-per-side lattice whose spacing {:.6g} is not larger "
        "than the largest sampled diameter {:.6g}; {}, narrow system.radius_distribution, "
        "or use initial.positions = \"random\"", c.source, n, side, spacing, 2.0 * largest,
        c.initial.lattice_spacing ? "raise initial.lattice_spacing" : "lower system.volume_fraction"));
  return lattice_sites<D>(n, side, spacing);
}

// A uniform point at which sphere i (radius r[i]) overlaps none placed before, or throws.
template <int D>
Vec<D> free_point(const Config& c, const Box<D>& box, const std::vector<double>& r, int i, int placed,
                  const CellGrid<D>& grid, Random& rng) {
  const double lo = box.periodic() ? 0.0 : r[i], hi = box.periodic() ? box.length : box.length - r[i];
  for (int tries = 0; tries < kMaxRandomPlacementTries; ++tries) {
    Vec<D> p;
    for (int a = 0; a < D; ++a) p[a] = box.wrap(rng.uniform(lo, hi));
    bool free = true;
    grid.for_each_near(p, [&](int j, const Vec<D>& xj) { free = free && box.separation(p, xj).norm() > r[i] + r[j]; });
    if (free) return p;
  }
  throw InputError(fmt::format(
      "{}: initial.positions = \"random\": sphere {} of {} (radius {:.6g}, placed largest first) found no free place "
      "in {} tries; the volume fraction is too high for random placement, lower system.volume_fraction or narrow "
      "system.radius_distribution", c.source, placed + 1, c.system.n, r[i], kMaxRandomPlacementTries));
}

template <int D>
std::vector<Vec<D>> random_points(const Config& c, const Box<D>& box, const std::vector<double>& r, double largest) {
  if (!box.periodic() && box.length <= 2.0 * largest)
    throw InputError(fmt::format("{}: the box length {:.6g} is not larger than the largest sampled diameter {:.6g}",
                                 c.source, box.length, 2.0 * largest));
  const int n = static_cast<int>(r.size());
  std::vector<int> largest_first(n);
  std::iota(largest_first.begin(), largest_first.end(), 0);
  std::stable_sort(largest_first.begin(), largest_first.end(), [&](int a, int b) { return r[a] > r[b]; });
  Random rng(c.initial.seed, RandomPurpose::positions);
  CellGrid<D> grid(box, 2.0 * largest, n);
  std::vector<Vec<D>> x(n);
  for (int k = 0; k < n; ++k) {
    const int i = largest_first[k];
    x[i] = free_point(c, box, r, i, k, grid, rng);
    grid.insert(i, x[i]);
  }
  return x;
}

}  // namespace

template <int D>
SphereTable<D> sized_spheres(const Config& c, const Box<D>& box) {
  const std::vector<double> r =
      sample_radii(c.system.radius_distribution, c.system.radius, c.system.n, c.initial.seed);
  const double largest = *std::max_element(r.begin(), r.end());
  const std::vector<Vec<D>> x = c.initial.positions == InitialPositions::lattice ? lattice_start<D>(c, box, largest)
                                                                                  : random_points<D>(c, box, r, largest);
  SphereTable<D> t;
  for (std::size_t i : z_order<D>(x, box)) {
    t.position.push_back(x[i]);
    t.radius.push_back(r[i]);
    t.mass.push_back(sphere_mass(c.system, r[i]));
  }
  return t;
}

template SphereTable<2> sized_spheres<2>(const Config&, const Box<2>&);
template SphereTable<3> sized_spheres<3>(const Config&, const Box<3>&);

}  // namespace ballagg
