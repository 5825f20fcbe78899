#pragma once
// Extended XYZ (read by OVITO and ASE): one frame with the box, positions, velocities,
// radius and cluster id of every sphere. 2D runs write z = 0.
#include <string>

#include "ballagg/core/state.hpp"

namespace ballagg {

template <int D>
std::string xyz_frame_text(const State<D>& state);

}  // namespace ballagg
