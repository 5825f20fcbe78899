#include "ballagg/initial/sphere_layout_check.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "ballagg/core/disjoint_sets.hpp"
#include "ballagg/core/parallel.hpp"
#include "ballagg/core/tolerances.hpp"
#include "ballagg/spatial/pair_scan.hpp"

namespace ballagg {
namespace {

struct SpherePair {
  std::int32_t i, j;  // i < j
  double overlap;     // (sigma - d) / sigma
};

// The pair met first in file order (lowest i, then lowest j): the same whatever the
// order the threads found them in.
const SpherePair* first_in_file_order(const std::vector<std::vector<SpherePair>>& found) {
  const SpherePair* first = nullptr;
  for (const auto& list : found)
    for (const SpherePair& p : list)
      if (!first || p.i < first->i || (p.i == first->i && p.j < first->j)) first = &p;
  return first;
}

template <int D>
std::string line_of(const SphereTable<D>& t, int i) {
  if (t.line.empty()) return fmt::format("sphere {}", i);
  return fmt::format("{}:{}", t.source, t.line[i]);
}

template <int D>
std::string other_sphere(const SphereTable<D>& t, int j) {
  if (t.line.empty()) return fmt::format("sphere {}", j);
  return fmt::format("the sphere of line {}", t.line[j]);
}

// For each sphere, the first sphere of the file with its cluster id. Ids written by
// ballagg are 0, 1, ...: a table indexed by id; any other ids go through a hash map.
template <int D>
std::vector<std::int32_t> first_of_cluster(const SphereTable<D>& t) {
  const int n = static_cast<int>(t.cluster.size());
  std::vector<std::int32_t> first(n);
  const auto [lo, hi] = std::minmax_element(t.cluster.begin(), t.cluster.end());
  if (*lo >= 0 && *hi < n) {
    std::vector<std::int32_t> by_id(n, -1);
    for (int i = 0; i < n; ++i) {
      std::int32_t& f = by_id[t.cluster[i]];
      if (f < 0) f = i;
      first[i] = f;
    }
    return first;
  }
  std::unordered_map<std::int64_t, std::int32_t> by_id;
  by_id.reserve(n);
  for (int i = 0; i < n; ++i) first[i] = by_id.emplace(t.cluster[i], i).first->second;
  return first;
}

}  // namespace

LayoutTolerance layout_tolerance(const Config& c) {
  LayoutTolerance tol{tolerance::kInputOverlap, tolerance::kContact};
  if (c.engine.kind != EngineKind::ts) return tol;
  tol.overlap = c.ts.daha.eps_c;
  switch (c.ts.model) {
    case TsModel::rigid: tol.contact = c.ts.daha.eps_c; break;
    case TsModel::almost_rigid: tol.contact = c.ts.daha.eps_c + c.ts.bond_stretch; break;
    case TsModel::non_rigid: tol.contact.reset(); break;
  }
  return tol;
}

template <int D>
void check_sphere_layout(const Box<D>& box, const SphereTable<D>& t, const LayoutTolerance& tol) {
  if (t.cluster.empty()) return;  // every sphere a cluster of its own
  const int n = static_cast<int>(t.radius.size());
  std::vector<Vec<D>> x(t.position);
  if (box.periodic())
    for (Vec<D>& p : x) p = box.wrap(p);
  const double r_max = *std::max_element(t.radius.begin(), t.radius.end());
  const double reach = 2.0 * r_max * (1.0 + tol.contact.value_or(0.0));
  std::vector<std::vector<SpherePair>> overlaps(max_threads()), contacts(max_threads());
  for_each_pair_within<D>(box, x, reach, [&](int thread, int a, int b, double d) {
    if (t.cluster[a] != t.cluster[b]) return;
    const double sigma = t.radius[a] + t.radius[b];
    const double overlap = (sigma - d) / sigma;
    const SpherePair p{std::min(a, b), std::max(a, b), overlap};
    if (overlap > tol.overlap) overlaps[thread].push_back(p);
    if (tol.contact && d <= sigma * (1.0 + *tol.contact)) contacts[thread].push_back(p);
  });
  if (const SpherePair* p = first_in_file_order(overlaps))
    throw InputError(fmt::format(
        "{}: this sphere overlaps {} of the same cluster ({}) by {:.3g} of their contact distance (spheres must not "
        "overlap by more than {} of it, glued or not)",
        line_of(t, p->i), other_sphere(t, p->j), t.cluster[p->i], p->overlap, tol.overlap));
  if (!tol.contact) return;
  DisjointSets pieces(n);
  for (const auto& list : contacts)
    for (const SpherePair& p : list) pieces.unite(p.i, p.j);
  const std::vector<std::int32_t> first = first_of_cluster(t);
  for (int i = 0; i < n; ++i) {
    if (pieces.find(i) == pieces.find(first[i])) continue;
    throw InputError(fmt::format(
        "{}: this sphere of cluster {} is not joined to {}, the cluster's first, by a chain of touching spheres "
        "(distance at most (R_i + R_j)(1 + {})): the spheres of a cluster must touch one another",
        line_of(t, i), t.cluster[i], other_sphere(t, first[i]), *tol.contact));
  }
}

template void check_sphere_layout<2>(const Box<2>&, const SphereTable<2>&, const LayoutTolerance&);
template void check_sphere_layout<3>(const Box<3>&, const SphereTable<3>&, const LayoutTolerance&);

}  // namespace ballagg
