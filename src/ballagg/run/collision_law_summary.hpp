#pragma once
// The collision law of a rigid-body run as summary.json states it ("collision_law"): how the
// impact energy is defined, the thresholds in effect and how they were derived, and the
// restitution law with its units. docs/outputs.md lists the keys.
#include <string>

#include "ballagg/config/config.hpp"

namespace ballagg {

// A JSON object (text), from the resolved configuration alone: a resumed run and a run of
// the resolved config.toml state the same.
std::string collision_law_json_text(const Config& resolved);

}  // namespace ballagg
