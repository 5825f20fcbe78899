#pragma once
// The velocity of two bodies that stick (rule 2.9): State::merge applies it, so it sits
// beside State; the other collision laws are in collision/laws.hpp, which includes it.
#include "ballagg/core/vec.hpp"

namespace ballagg {

// Sticking (rule 2.9): the merged body moves with the mass-weighted mean velocity.
// Conserves momentum exactly up to one rounding per component.
template <int D>
Vec<D> stick_velocity(double m1, const Vec<D>& v1, double m2, const Vec<D>& v2) {
  return (m1 * v1 + m2 * v2) / (m1 + m2);
}

}  // namespace ballagg
