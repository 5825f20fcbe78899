#pragma once
// The mass spectrum: how many clusters there are of each size (number of spheres) and
// mass, the histogram of Richardson 1995, Figs. 3c-d (there with masses in units of one
// sphere's). Size and mass go together for equal spheres that stick; they part when
// colliding spheres coalesce into one heavier sphere (the rigid-body engine's
// `collision.coagulation = "sphere"`, Richardson's models i and ii: every body then has
// size 1 and the spectrum is one of masses).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace ballagg {

// Masses of clusters of one size that agree to this relative precision share a bin: sums
// of the same sphere masses added in another order differ by round-off only.
inline constexpr double kMassSpectrumTolerance = 1e-12;

struct MassSpectrumBin {
  std::int32_t size = 0;      // spheres per cluster
  double mass = 0.0;          // their mass (the smallest in the bin)
  std::int64_t clusters = 0;  // clusters of that size and mass
};

// From (size, mass) per cluster: ascending sizes, then masses, only those that occur.
inline std::vector<MassSpectrumBin> mass_spectrum(std::vector<std::pair<std::int32_t, double>> size_and_mass) {
  std::sort(size_and_mass.begin(), size_and_mass.end());
  std::vector<MassSpectrumBin> bins;
  for (const auto& [size, mass] : size_and_mass) {
    const bool same = !bins.empty() && bins.back().size == size &&
                      mass - bins.back().mass <= kMassSpectrumTolerance * std::abs(bins.back().mass);
    if (same) ++bins.back().clusters;
    else bins.push_back({size, mass, 1});
  }
  return bins;
}

}  // namespace ballagg
