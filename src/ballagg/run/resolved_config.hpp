#pragma once
// The configuration a run resolves at its start, without running it (`ballagg config`).
#include "ballagg/config/config.hpp"

namespace ballagg {

// `given` with the keys whose defaults depend on the initial state filled in (engine.skin,
// collision.tc_time, ...; resolve_defaults in simulation.hpp): the configuration that
// `ballagg run` writes to config.toml for the same arguments. Builds the initial state to
// find them, so it refuses (InputError) whatever a run would refuse before it starts.
Config resolved_config(const Config& given);

}  // namespace ballagg
