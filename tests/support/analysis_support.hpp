#pragma once
// Hand-built sets of sphere centres with known shapes, for the analysis tests.
#include <cmath>
#include <cstdint>
#include <vector>

#include "ballagg/analysis/aggregate_analysis.hpp"
#include "ballagg/io/state_csv.hpp"

namespace ballagg::testing {

// Spheres of radius r and mass 1 at `centres`, all glued into cluster `label`.
template <int D>
void add_spheres(SphereTable<D>& t, const std::vector<Vec<D>>& centres, double r, std::int64_t label) {
  for (const Vec<D>& x : centres) {
    t.position.push_back(x);
    t.velocity.push_back(Vec<D>::Zero());
    t.radius.push_back(r);
    t.mass.push_back(1.0);
    t.cluster.push_back(label);
    t.line.push_back(static_cast<int>(t.radius.size()) + 1);
  }
}

template <int D>
SphereTable<D> one_cluster(const std::vector<Vec<D>>& centres, double r) {
  SphereTable<D> t;
  add_spheres(t, centres, r, 0);
  return t;
}

// n touching spheres of radius r along direction u from `start`.
template <int D>
std::vector<Vec<D>> chain(const Vec<D>& start, const Vec<D>& u, int n, double r) {
  std::vector<Vec<D>> x;
  for (int k = 0; k < n; ++k) x.push_back(start + 2.0 * r * k * u.normalized());
  return x;
}

// A square (cubic in 3D) lattice of side `per_side` spheres touching (spacing 2r), its
// first centre at `corner`.
template <int D>
std::vector<Vec<D>> lattice(const Vec<D>& corner, int per_side, double r) {
  std::vector<Vec<D>> x;
  const int total = static_cast<int>(std::pow(per_side, D));
  for (int k = 0; k < total; ++k) {
    Vec<D> p = corner;
    for (int a = 0, rest = k; a < D; ++a, rest /= per_side) p[a] += 2.0 * r * (rest % per_side);
    x.push_back(p);
  }
  return x;
}

// The Sierpinski triangle of 3^levels touching spheres: row i, place j of Pascal's
// triangle is kept when C(i, j) is odd (j & (i - j) == 0), on a triangular lattice of
// spacing 2r (equilateral), the lower-left corner at `corner`.
inline std::vector<Vec<2>> sierpinski(const Vec<2>& corner, int levels, double r) {
  std::vector<Vec<2>> x;
  const int rows = 1 << levels;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j <= i; ++j)
      if ((j & (i - j)) == 0) {
        const double across = (rows - 1 - i) + 2.0 * j;  // in units of r
        x.push_back(corner + Vec<2>(across * r, (rows - 1 - i) * std::sqrt(3.0) * r));
      }
  return x;
}

}  // namespace ballagg::testing
