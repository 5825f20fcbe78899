#pragma once
// `ballagg verify RUN_DIR`: an independent check of a finished run from its files alone
// (final.csv, summary.json, config.toml, timeseries.csv), sharing no code with the
// engines: the geometry (no overlaps beyond tolerance, centres in the box), the clusters
// (rigid: one velocity; connected: every cluster's spheres form one contact graph), the
// budgets (mass; momentum, the walls' impulse accounted for; kinetic energy never
// created) and the summary's counts and totals against the final state. docs/verify.md.
#include <string>
#include <vector>

namespace ballagg {

// Relative tolerances of the checks (docs/verify.md).
namespace verify_tolerance {
// Overlap and contact, as fractions of sigma = R_i + R_j, for the event-driven engines
// (exact contacts, round-off only); the time-stepping engine is allowed its ts.daha.eps_c
// (and, in its per-sphere models, the largest link stretch the summary reports).
inline constexpr double kExactContact = 1e-9;
// Sums recomputed from final.csv against summary.json (both printed round-trip exact;
// the summary's sums and ours add the same numbers in a different order).
inline constexpr double kSum = 1e-9;
// Momentum and energy budgets, relative to sqrt(2 M E_0) and E_0: the round-off of
// millions of collisions stays orders of magnitude below.
inline constexpr double kBudget = 1e-8;
}  // namespace verify_tolerance

struct Verification {
  int checks = 0;                     // checks made
  std::vector<std::string> violations;  // one line each
  std::vector<std::string> notes;       // checks that could not be made, and why
};

// Throws InputError when dir is not a readable run directory.
Verification verify_run(const std::string& dir);

}  // namespace ballagg
