#pragma once
// The relative number of contacts per sphere (Degond et al. 2023, eq. 4.5):
//   N_c = 1 / (N N_max) * sum_{i != j} 1{|X_i - X_j| <= alpha_R R}
// Two centres closer than alpha_R R are "in contact": alpha_R = 2.1 rather than 2 because
// the time-stepping minimisation leaves gaps of a few 1e-3 diameters. N_max is the most
// spheres that can touch one sphere: 6 in 2D (hexagonal packing), 12 in 3D (the kissing
// number). With unequal radii the threshold is alpha_R (R_i + R_j) / 2.
//
// The sum as printed runs over all i, j, so it also counts each sphere with itself and adds
// exactly 1 / N_max; the text describes contacts with *other* spheres ("in contact in
// average with other three" for N_c = 0.5). We report both: `contacts` (i != j, the
// physical count, 1/6 ... 1 in 2D for a connected cluster) and `contacts_with_self`
// (= contacts + 1/N_max, eq. 4.5 taken literally). docs/analysis.md discusses which one
// the paper's Fig. 8 values match.
#include <cstdint>
#include <vector>

#include "ballagg/core/box.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

inline constexpr double kContactFactor = 2.1;  // alpha_R of (4.5)

template <int D>
inline constexpr int kMaxContacts = D == 2 ? 6 : 12;  // N_max of (4.5)

struct ContactCounts {
  std::vector<std::int32_t> all;           // per sphere: spheres in contact with it
  std::vector<std::int32_t> same_cluster;  // ... of these, those of its own cluster
};

// label: per sphere its cluster (ClusterPartition::label).
template <int D>
ContactCounts count_contacts(const Box<D>& box, const std::vector<Vec<D>>& position, const std::vector<double>& radius,
                             const std::vector<std::int32_t>& label, double alpha_r = kContactFactor);

// N_c (4.5) of a set of spheres from their contact counts: sum / (n N_max).
template <int D>
double relative_contacts(std::int64_t contact_sum, std::int64_t n_spheres) {
  return n_spheres > 0 ? static_cast<double>(contact_sum) / (static_cast<double>(n_spheres) * kMaxContacts<D>) : 0.0;
}

// Eq. (4.5) with the sum over all i, j including i = j, as printed.
template <int D>
double relative_contacts_with_self(double contacts) {
  return contacts + 1.0 / kMaxContacts<D>;
}

extern template ContactCounts count_contacts<2>(const Box<2>&, const std::vector<Vec<2>>&, const std::vector<double>&,
                                                const std::vector<std::int32_t>&, double);
extern template ContactCounts count_contacts<3>(const Box<3>&, const std::vector<Vec<3>>&, const std::vector<double>&,
                                                const std::vector<std::int32_t>&, double);

}  // namespace ballagg
