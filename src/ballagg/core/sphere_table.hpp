#pragma once
// Spheres as a table of rows, one per sphere: what a state file holds (io/state_csv.hpp
// reads and writes the format), what an initial state is assembled from
// (initial/initial_state.hpp) and what the aggregate analysis reads (analysis/).
#include <cstdint>
#include <string>
#include <vector>

#include "ballagg/core/spin.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

template <int D>
struct SphereTable {
  std::vector<Vec<D>> position, velocity;
  std::vector<double> radius, mass;
  std::vector<std::int64_t> cluster;  // empty when the file has no cluster column
  std::vector<Spin<D>> spin;          // empty when the file has no spin columns
  std::vector<int> line;              // file line of each sphere, for error messages
  std::string source;                 // file name
};

}  // namespace ballagg
