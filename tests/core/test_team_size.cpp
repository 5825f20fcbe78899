// The team of the parallel regions on a shared machine (core/team_size_rule.hpp,
// core/adaptive_team.hpp): the rule's decisions on given measures, which settings leave
// the team to OpenMP, and that a run gives the calling thread its thread count back. No
// timing: the measures are given, or only their form is checked.
#include <omp.h>

#include <cstdlib>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "ballagg/core/adaptive_team.hpp"
#include "ballagg/core/cpu_load.hpp"
#include "ballagg/core/run_delay.hpp"
#include "ballagg/core/team_size_rule.hpp"

namespace ballagg {
namespace {

constexpr double kSample = kTeamSampleSeconds;

// Two threads on two cores beside one busy process wait about 2/3 of a core in all.
constexpr double kWaitBesideABusyProcess = 0.67 * kSample;
constexpr double kWaitAlone = 0.002 * kSample;

TEST(TeamSizeRule, GivesOneThreadWhenTheThreadsWaitForATakenCore) {
  TeamSizeRule rule(2);
  EXPECT_EQ(rule.team(), 2);
  EXPECT_EQ(rule.after_sample(10.0, kSample, kWaitBesideABusyProcess), 1);
  // One thread beside the busy process waits for nothing; it stays one until the retry.
  EXPECT_EQ(rule.after_sample(10.0 + kSample, kSample, 0.0), 1);
}

TEST(TeamSizeRule, KeepsTheFullTeamWhileItsThreadsDoNotWait) {
  TeamSizeRule rule(2);
  for (int k = 1; k <= 100; ++k) EXPECT_EQ(rule.after_sample(k * kSample, kSample, kWaitAlone), 2);
  // Just below the threshold: kept.
  EXPECT_EQ(rule.after_sample(101 * kSample, kSample, 0.99 * kTeamWaitingToShrink * kSample), 2);
}

TEST(TeamSizeRule, GivesUpAThreadPerCoreWaitedFor) {
  TeamSizeRule rule(8);
  // Eight threads on eight cores beside four busy processes: 8 * 4 / 12 cores waited.
  EXPECT_EQ(rule.after_sample(1.0, kSample, 8.0 * 4.0 / 12.0 * kSample), 5);
  // Five beside four on eight cores: 5 / 9.
  EXPECT_EQ(rule.after_sample(1.0 + kSample, kSample, 5.0 / 9.0 * kSample), 4);
  EXPECT_EQ(rule.after_sample(1.0 + 2 * kSample, kSample, 0.0), 4);
  // However much is waited, one thread is left.
  EXPECT_EQ(rule.after_sample(1.0 + 3 * kSample, kSample, 100.0 * kSample), 1);
}

TEST(TeamSizeRule, TriesTheFullTeamAgainAndWaitsTwiceAsLongAfterEachFailedTry) {
  TeamSizeRule rule(2);
  double now = 1.0;
  EXPECT_EQ(rule.after_sample(now, kSample, kWaitBesideABusyProcess), 1);
  double wait = kFirstTeamRetrySeconds;
  for (int attempt = 0; attempt < 8; ++attempt) {
    const double shrunk_at = now;
    EXPECT_EQ(rule.after_sample(shrunk_at + 0.99 * wait, kSample, 0.0), 1) << "attempt " << attempt;
    now = shrunk_at + wait;
    EXPECT_EQ(rule.after_sample(now, kSample, 0.0), 2) << "attempt " << attempt;  // the try
    now += kSample;
    EXPECT_EQ(rule.after_sample(now, kSample, kWaitBesideABusyProcess), 1);  // failed
    wait = std::min(2.0 * wait, kLongestTeamRetrySeconds);
  }
  EXPECT_EQ(wait, kLongestTeamRetrySeconds);
  EXPECT_EQ(rule.after_sample(now + 0.99 * wait, kSample, 0.0), 1);
  EXPECT_EQ(rule.after_sample(now + wait, kSample, 0.0), 2);
}

TEST(TeamSizeRule, ATryThatKeepsTheTeamRestoresTheFirstRetryWait) {
  TeamSizeRule rule(2);
  EXPECT_EQ(rule.after_sample(1.0, kSample, kWaitBesideABusyProcess), 1);
  EXPECT_EQ(rule.after_sample(1.0 + kFirstTeamRetrySeconds, kSample, 0.0), 2);
  EXPECT_EQ(rule.after_sample(1.0 + kFirstTeamRetrySeconds + kSample, kSample, 0.0), 2);  // the try held
  // A busy process comes later: the first retry wait again.
  const double shrunk_at = 50.0;
  EXPECT_EQ(rule.after_sample(shrunk_at, kSample, kWaitBesideABusyProcess), 1);
  EXPECT_EQ(rule.after_sample(shrunk_at + kFirstTeamRetrySeconds, kSample, 0.0), 2);
}

TEST(TeamSizeRule, StartsWithTheCoresOthersLeaveFree) {
  EXPECT_EQ(starting_team(2, 2, 0), 2);
  EXPECT_EQ(starting_team(2, 2, 1), 1);
  EXPECT_EQ(starting_team(2, 2, 6), 1);
  EXPECT_EQ(starting_team(8, 8, 3), 5);
  EXPECT_EQ(starting_team(2, 8, 1), 2);  // never more than OpenMP gives
  TeamSizeRule rule(2);
  rule.start_with(starting_team(2, 2, 1), 3.0);
  EXPECT_EQ(rule.team(), 1);
  EXPECT_EQ(rule.after_sample(3.0 + kSample, kSample, 0.0), 1);
  EXPECT_EQ(rule.after_sample(3.0 + kFirstTeamRetrySeconds, kSample, 0.0), 2);  // tried as after a shrink
}

TEST(TeamSizing, AUserWhoSetsTheThreadCountOrDynamicAdjustmentChoosesTheTeam) {
  EXPECT_EQ(team_sizing_from_environment(nullptr, nullptr), TeamSizing::adaptive);
  EXPECT_EQ(team_sizing_from_environment("", ""), TeamSizing::adaptive);
  EXPECT_EQ(team_sizing_from_environment("2", nullptr), TeamSizing::openmp);
  EXPECT_EQ(team_sizing_from_environment("1", nullptr), TeamSizing::openmp);
  EXPECT_EQ(team_sizing_from_environment(nullptr, "false"), TeamSizing::openmp);
  EXPECT_EQ(team_sizing_from_environment(nullptr, "true"), TeamSizing::openmp);
}

// OMP_NUM_THREADS and OMP_DYNAMIC unset for the object's lifetime (the suite runs with
// OMP_NUM_THREADS=1), restored when it goes.
class WithoutOmpVariables {
 public:
  WithoutOmpVariables() {
    for (int k = 0; k < 2; ++k) {
      if (const char* v = std::getenv(kNames[k])) saved_[k] = v;
      unsetenv(kNames[k]);
    }
  }
  ~WithoutOmpVariables() {
    for (int k = 0; k < 2; ++k)
      if (saved_[k]) setenv(kNames[k], saved_[k]->c_str(), 1);
  }

 private:
  static constexpr const char* kNames[2] = {"OMP_NUM_THREADS", "OMP_DYNAMIC"};
  std::optional<std::string> saved_[2];
};

TEST(AdaptiveTeam, GivesTheCallingThreadItsThreadCountBack) {
  const WithoutOmpVariables unset;
  const int before = omp_get_max_threads();
  omp_set_num_threads(3);
  {
    AdaptiveTeam team;
    team.poll();
    EXPECT_GE(omp_get_max_threads(), 1);
    EXPECT_LE(omp_get_max_threads(), 3);
  }
  EXPECT_EQ(omp_get_max_threads(), 3);
  omp_set_num_threads(before);
}

TEST(AdaptiveTeam, LeavesTheTeamAloneWhenPinnedOrSetByTheUser) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(3);
  {
    const WithoutOmpVariables unset;
    const PinnedTeamSize pinned;
    AdaptiveTeam team;
    EXPECT_EQ(omp_get_max_threads(), 3);
  }
  {
    const WithoutOmpVariables unset;
    setenv("OMP_NUM_THREADS", "3", 1);
    AdaptiveTeam team;
    EXPECT_EQ(omp_get_max_threads(), 3);
    unsetenv("OMP_NUM_THREADS");
  }
  // Inside a parallel region (a sweep's runs): the sweep chose the team.
  {
    const WithoutOmpVariables unset;
    int inside = 0;
#pragma omp parallel num_threads(1)
    {
      omp_set_num_threads(3);
      AdaptiveTeam team;
      inside = omp_get_max_threads();
    }
    EXPECT_EQ(inside, 3);
  }
  omp_set_num_threads(before);
}

TEST(CpuReadings, AreReportedByThisKernel) {
  RunDelayMeter meter;
  const std::optional<double> first = meter.waited_since_last();
  if (!first) GTEST_SKIP() << "this kernel does not report the threads' waits (CONFIG_SCHED_INFO)";
  EXPECT_EQ(*first, 0.0);
  const std::optional<double> second = meter.waited_since_last();
  ASSERT_TRUE(second.has_value());
  EXPECT_GE(*second, 0.0);
  EXPECT_GE(allowed_cpus(), 1);
  const std::optional<int> elsewhere = runnable_elsewhere();
  ASSERT_TRUE(elsewhere.has_value());
  EXPECT_GE(*elsewhere, 0);
}

}  // namespace
}  // namespace ballagg
