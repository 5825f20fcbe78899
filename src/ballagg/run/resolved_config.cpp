#include "ballagg/run/resolved_config.hpp"

#include "ballagg/initial/initial_state.hpp"
#include "ballagg/run/simulation.hpp"

namespace ballagg {
namespace {

template <int D>
Config resolved_in_dimension(const Config& given) {
  return resolve_defaults(given, make_initial_state<D>(given));
}

}  // namespace

Config resolved_config(const Config& given) {
  if (given.system.dimension == 2) return resolved_in_dimension<2>(given);
  return resolved_in_dimension<3>(given);
}

}  // namespace ballagg
