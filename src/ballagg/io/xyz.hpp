#pragma once
// Extended XYZ (read by OVITO and ASE): frames with the box, positions, velocities,
// radius and cluster id of every sphere. 2D runs write z = 0. A trajectory is frames one
// after the other.
#include <string>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/state.hpp"
#include "ballagg/io/frame.hpp"

namespace ballagg {

template <int D>
void append_xyz_frame(std::string& out, const Frame<D>& frame, const Particles<D>& particles);

// The state at state.time as one frame (final.xyz).
template <int D>
std::string xyz_frame_text(const State<D>& state);
// The same texts handed to `out` in chunks of about kTextChunkBytes (chunked_text.hpp).
template <int D>
void write_xyz_frame(const Frame<D>& frame, const Particles<D>& particles, ByteSink& out);
template <int D>
void write_xyz_frame(const State<D>& state, ByteSink& out);

}  // namespace ballagg
