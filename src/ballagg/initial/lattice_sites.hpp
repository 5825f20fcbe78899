#pragma once
// The simple-cubic (square in 2D) lattice of the generated starts: monodisperse
// (initial_state.cpp) and polydisperse (polydisperse_start.cpp) fill it the same way and
// differ only in the diameter the spacing must exceed, so each checks its own and words its
// own message.
#include <cstdint>
#include <vector>

#include "ballagg/config/config.hpp"
#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

// The spacing of the lattice: App. A's given spacing (which sets the box through
// resolved_box_length, so it is taken as given and not divided back out of the box), or the
// box length over the sites per side.
template <int D>
double lattice_spacing(const Config& c, const Box<D>& box) {
  return c.initial.lattice_spacing.value_or(box.length / static_cast<double>(lattice_side(c.system.n, D)));
}

// The first n sites of a lattice of `side` sites per axis, at the centres of its cells
// ((k + 1/2) spacing), filled along axis 0 first.
template <int D>
std::vector<Vec<D>> lattice_sites(std::int64_t n, std::int64_t side, double spacing) {
  std::vector<Vec<D>> x(n);
  for (std::int64_t k = 0; k < n; ++k) {
    std::int64_t rest = k;
    for (int a = 0; a < D; ++a) {
      x[k][a] = (static_cast<double>(rest % side) + 0.5) * spacing;
      rest /= side;
    }
  }
  return x;
}

}  // namespace ballagg
