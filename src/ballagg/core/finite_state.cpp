#include "ballagg/core/finite_state.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace ballagg {
namespace {

template <int V>
std::string components(const Eigen::Matrix<double, V, 1>& v) {
  return fmt::format("({})", fmt::join(v.data(), v.data() + V, ", "));
}

template <int D>
std::optional<std::string> sphere_non_finite(const State<D>& s, int i) {
  // The velocity first: a position is computed from it (positions are lazy).
  const Vec<D>& v = s.velocity(i);
  if (!v.allFinite()) return fmt::format("the velocity of sphere {} is {}", i, components(v));
  const Vec<D> x = s.unwrapped_position(i, s.time);
  if (!x.allFinite()) return fmt::format("the position of sphere {} is {}", i, components(x));
  if (!s.spin.empty()) {
    const Spin<D>& w = s.spin[s.spheres.cluster[i]].angular_velocity;
    if (!w.allFinite()) return fmt::format("the angular velocity of sphere {} is {}", i, components(w));
  }
  return std::nullopt;
}

template <int D>
std::optional<std::string> time_non_finite(const State<D>& s) {
  if (!std::isfinite(s.time)) return fmt::format("the time is {}", s.time);
  return std::nullopt;
}

}  // namespace

template <int D>
std::optional<std::string> first_non_finite(const State<D>& s) {
  if (auto what = time_non_finite(s)) return what;
  for (int i = 0; i < s.n_spheres(); ++i)
    if (auto what = sphere_non_finite(s, i)) return what;
  return std::nullopt;
}

template <int D>
std::optional<std::string> first_non_finite(const State<D>& s, std::span<const int> spheres) {
  if (auto what = time_non_finite(s)) return what;
  for (int i : spheres)
    if (auto what = sphere_non_finite(s, i)) return what;
  return std::nullopt;
}

template <int D>
void throw_if_not_finite(const State<D>& s, std::string_view engine, const std::optional<std::string>& what) {
  if (what)
    throw NonFiniteState(
        fmt::format("the {} engine made a state that is not finite at t = {}: {}", engine, s.time, *what));
}

#define BALLAGG_FINITE_STATE(D)                                                                      \
  template std::optional<std::string> first_non_finite<D>(const State<D>&);                         \
  template std::optional<std::string> first_non_finite<D>(const State<D>&, std::span<const int>);   \
  template void throw_if_not_finite<D>(const State<D>&, std::string_view, const std::optional<std::string>&);
BALLAGG_FINITE_STATE(2)
BALLAGG_FINITE_STATE(3)
#undef BALLAGG_FINITE_STATE

}  // namespace ballagg
