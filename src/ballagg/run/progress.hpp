#pragma once
// Progress of a run on stderr: a bar redrawn in place on a terminal, a plain line every
// kPlainEvery seconds otherwise (log files), nothing with --quiet (core/progress_line.hpp).
#include <chrono>
#include <cstdio>

#include "ballagg/core/progress_line.hpp"
#include "ballagg/engines/engine.hpp"

namespace ballagg {

template <int D>
class ProgressReporter final : public RunObserver<D> {
 public:
  static constexpr double kTerminalEvery = ProgressLine::kTerminalEvery;  // seconds between redraws
  static constexpr double kPlainEvery = ProgressLine::kPlainEvery;        // seconds between plain lines

  ProgressReporter(std::FILE* out, bool terminal, const StopCriteria& stop)
      : out_(out), terminal_(terminal), stop_(stop) {}

  void on_start(const State<D>& s) override;
  void after_event(const State<D>& s, const EventRecord&, const EngineCounters& c) override;
  void on_finish(const State<D>& s, const RunResult& r) override;

 private:
  enum class Moment { running, ended, cut };
  void report(const State<D>& s, std::int64_t events, Moment moment);
  double seconds() const;

  std::FILE* out_;
  bool terminal_;
  StopCriteria stop_;
  int initial_clusters_ = 0;
  double last_report_ = 0.0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace ballagg
