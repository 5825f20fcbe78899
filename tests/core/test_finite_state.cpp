// The guard against a state that is not finite (core/finite_state.hpp): which value it
// names, and the one line a run stops with.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/core/finite_state.hpp"
#include "support.hpp"

namespace ballagg {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Three discs; the first two glued into one cluster.
State<2> three_discs() {
  using testing::Ball;
  return testing::make_state<2>(10.0, Boundary::periodic,
                                {Ball<2>{Vec<2>(1.0, 1.0), Vec<2>(0.5, 0.0), 0.5, 1.0, 7},
                                 Ball<2>{Vec<2>(2.0, 1.0), Vec<2>(0.5, 0.0), 0.5, 1.0, 7},
                                 Ball<2>{Vec<2>(5.0, 5.0), Vec<2>(-1.0, 0.0), 0.5, 1.0, -1}});
}

TEST(FiniteState, AFiniteStateHasNothingToName) {
  const State<2> s = three_discs();
  EXPECT_FALSE(first_non_finite(s).has_value());
  EXPECT_NO_THROW(throw_if_not_finite(s, "ts", first_non_finite(s)));
}

TEST(FiniteState, NamesTheFirstSphereWhoseVelocityIsNotFinite) {
  State<2> s = three_discs();
  s.clusters[s.spheres.cluster[2]].velocity = Vec<2>(kNan, 1.0);
  const auto what = first_non_finite(s);
  ASSERT_TRUE(what.has_value());
  EXPECT_EQ(*what, "the velocity of sphere 2 is (nan, 1)");
}

TEST(FiniteState, NamesAPositionThatIsNotFiniteThroughTheAnchorOrTheOffset) {
  State<2> s = three_discs();
  s.spheres.offset[1] = Vec<2>(kInf, 0.0);
  EXPECT_EQ(first_non_finite(s).value_or(""), "the position of sphere 1 is (inf, 0)");
  s = three_discs();
  s.clusters[s.spheres.cluster[0]].anchor[1] = kNan;  // both spheres of the cluster
  EXPECT_EQ(first_non_finite(s).value_or(""), "the position of sphere 0 is (1, nan)");
}

TEST(FiniteState, NamesTheTimeAndTheSpin) {
  State<2> s = three_discs();
  s.time = kNan;
  EXPECT_EQ(first_non_finite(s).value_or(""), "the time is nan");
  s = three_discs();
  s.spin.resize(s.clusters.size());
  s.spin[s.spheres.cluster[2]].angular_velocity = Spin<2>(kInf);
  EXPECT_EQ(first_non_finite(s).value_or(""), "the angular velocity of sphere 2 is (inf)");
}

TEST(FiniteState, TheCheckOfSomeSpheresReadsOnlyThose) {
  State<2> s = three_discs();
  s.clusters[s.spheres.cluster[2]].velocity = Vec<2>(kNan, kNan);
  const std::vector<int> glued{0, 1}, lone{2};
  EXPECT_FALSE(first_non_finite<2>(s, glued).has_value());
  EXPECT_EQ(first_non_finite<2>(s, lone).value_or(""), "the velocity of sphere 2 is (nan, nan)");
}

TEST(FiniteState, ARunStopsWithOneLineNamingTheEngineTheTimeAndTheValue) {
  State<2> s = three_discs();
  s.time = 2.5;
  s.spheres.offset[2] = Vec<2>(kNan, kNan);
  try {
    throw_if_not_finite(s, "ts", first_non_finite(s));
    ADD_FAILURE() << "expected NonFiniteState";
  } catch (const NonFiniteState& e) {
    EXPECT_EQ(std::string(e.what()),
              "the ts engine made a state that is not finite at t = 2.5: the position of sphere 2 is (nan, nan)");
  }
}

}  // namespace
}  // namespace ballagg
