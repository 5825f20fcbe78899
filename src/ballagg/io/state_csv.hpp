#pragma once
// The state file format, read by `initial.file` and written as final.csv:
//   x,y,vx,vy,radius,mass[,cluster]            (2D)
//   x,y,z,vx,vy,vz,radius,mass[,cluster]       (3D)
// Columns may come in any order; lines starting with '#' and blank lines are skipped.
// Spheres with the same `cluster` value form one rigid cluster. Optional spin columns give
// each cluster's angular velocity: wz (2D) or wx,wy,wz (3D); final.csv of a rigid-body run
// has them.
#include <string>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/sphere_table.hpp"
#include "ballagg/core/state.hpp"

namespace ballagg {

// Throws InputError naming the file line for any malformed content.
template <int D>
SphereTable<D> read_state_csv(const std::string& path);
template <int D>
SphereTable<D> parse_state_csv(const std::string& text, const std::string& source);

// The state at time state.time in the same format, positions folded into the box, cluster
// ids numbered 0, 1, ... in order of each cluster's first sphere. Numbers are written in
// the shortest form that reads back to the same double, so files round-trip exactly.
template <int D>
std::string state_csv_text(const State<D>& state);
// The same text handed to `out` in chunks of about kTextChunkBytes (chunked_text.hpp).
template <int D>
void write_state_csv(const State<D>& state, ByteSink& out);

}  // namespace ballagg
