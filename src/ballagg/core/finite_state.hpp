#pragma once
// The guard against a state that is not made of finite numbers. No valid input makes one
// (docs/hardening.md), so a NaN or an infinity in the state is a numerical failure of an
// engine: the run stops with one line naming the engine, the time and the value, exit
// status 1, and nothing of it written, instead of ending with NaN in its files.
//
// The checks read the state only (what the output would show: the spheres' positions at
// the state's time, the clusters' velocities and spins, the time): O(N) for the whole
// state, O(k) for k spheres. Engines call them once per step or at the end of a run, never
// per pair.
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "ballagg/core/state.hpp"

namespace ballagg {

class NonFiniteState : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The first value of the state that is not finite, in words ("the position of sphere 12
// is (nan, nan)"), or nothing: the time, each sphere's position and its cluster's velocity,
// and the clusters' spins when they rotate.
template <int D>
std::optional<std::string> first_non_finite(const State<D>& s);
// The same over the given spheres only (and the time): what a step of an engine moved.
template <int D>
std::optional<std::string> first_non_finite(const State<D>& s, std::span<const int> spheres);

// Throws NonFiniteState, "the ENGINE engine made a state that is not finite at t = T: WHAT",
// when `what` holds a value.
template <int D>
void throw_if_not_finite(const State<D>& s, std::string_view engine, const std::optional<std::string>& what);

}  // namespace ballagg
