#pragma once
// The [ts] section of a configuration: the time-stepping engine's settings.
#include <set>
#include <string>

#include <toml++/toml.h>

#include "ballagg/engines/time_stepping/ts_settings.hpp"

namespace ballagg {

// [ts]: the time-stepping engine and its minimiser (docs/time_stepping.md). Throws
// InputError naming the key and what is allowed.
TimeSteppingSettings read_ts_section(const toml::table& root, const std::string& source,
                                     const std::set<std::string>& overridden);

}  // namespace ballagg
