#pragma once
// A command-line override "section.key=value" (--set) applied to a TOML document.
#include <set>
#include <string>

#include <toml++/toml.h>

namespace ballagg {

// Turns "section.key=value" into a TOML value in root; the value is read as TOML when it
// parses (numbers, booleans, quoted strings) and as a bare string otherwise (engine.kind=ed).
// Adds "section.key" to `overridden`. Throws InputError for an argument that is not of
// that form, holds a control character or is not UTF-8.
void apply_override(toml::table& root, const std::string& arg, std::set<std::string>& overridden);

}  // namespace ballagg
