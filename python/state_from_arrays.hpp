#pragma once
// A state given in Python as numpy arrays (ballagg.State.from_arrays): its spheres and box.
#include <variant>

#include "ballagg/config/config.hpp"
#include "ballagg/core/sphere_table.hpp"

namespace ballagg::python {

struct ArrayState {
  int dimension = 2;
  double box_length = 0.0;
  std::variant<SphereTable<2>, SphereTable<3>> spheres;
};

// The configuration of a simulation that starts from `s`: its box length and number of
// spheres in place of the configuration's (whose dimension must be the state's).
template <int D>
Config config_for_state(Config c, const ArrayState& s);

}  // namespace ballagg::python
