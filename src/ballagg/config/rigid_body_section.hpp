#pragma once
// The [collision] keys of the rigid-body engine (docs/rigid_body.md), and the rules that tie
// them to the rest of the configuration.
#include <string>
#include <vector>

#include "ballagg/config/config.hpp"
#include "ballagg/config/section_reader.hpp"

namespace ballagg {

// Reads them into k; returns the names of those given, so that other engines can refuse them.
std::vector<std::string> read_rigid_body_keys(SectionReader& col, RigidBodyLaw& k);

// Throws InputError when a rigid-body key is given for another engine, or the keys given
// contradict each other or the collision outcome.
void check_rigid_body_rules(const Config& c, const std::vector<std::string>& given, bool restitution_given);

}  // namespace ballagg
