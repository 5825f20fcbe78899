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

// Sets the energies a rigid-body run derives from the initial mean kinetic energy per body
// (translation and rotation, over the bodies at the start): energy_threshold =
// energy_threshold_factor x it (collision.outcome = "energy-threshold", the threshold not
// given as an energy; Richardson §3) and fragmentation_energy = fragmentation_factor x it
// (collision.fragmentation = "initial-energy"; §2.6). The factors are set as well, so that the
// resolved configuration states the derivation. An energy given beside its factor must be
// that multiple exactly (it is the resolved configuration of the same start): otherwise
// throws InputError naming both keys.
void resolve_rigid_body_energies(Config& c, double initial_mean_energy);

}  // namespace ballagg
