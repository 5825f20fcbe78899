// The vector helpers of core/vec.hpp.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "ballagg/core/vec.hpp"

namespace ballagg {
namespace {

// The quick rejection on squared distances (beyond_squared) of the contact passes and the
// retreat's searches: a pair at the bound, as the exact test computes its distance, is
// never rejected, at any scale; a pair a millionth beyond it always is.
TEST(QuickReject, NeverDropsAPairThatTheExactTestKeeps) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-6.0, 6.0);
  for (int k = 0; k < 200000; ++k) {
    const double scale = std::pow(10.0, exponent(rng));
    const Vec<3> a(unit(rng) * scale, unit(rng) * scale, unit(rng) * scale);
    const Vec<3> b(unit(rng) * scale, unit(rng) * scale, unit(rng) * scale);
    const Vec<3> d = a - b;
    const double bound = d.norm();  // the exact test keeps this pair: d.norm() <= bound
    ASSERT_LE(d.squaredNorm(), beyond_squared(bound)) << k;
    ASSERT_GT(d.squaredNorm(), beyond_squared(bound * (1.0 - 1e-6))) << k;
  }
}

}  // namespace
}  // namespace ballagg
