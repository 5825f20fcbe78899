#pragma once
// Progress on a stream (stderr): on a terminal a bar redrawn in place, a few times a
// second; otherwise (a log file, a pipe) a plain line every kPlainEvery seconds, since each
// line stays. The run's progress (run/progress.hpp) and a video's (ballagg render --video)
// draw it alike.
#include <chrono>
#include <cstdio>
#include <string>

namespace ballagg {

// One report: `done` (0 to 1) as a bar and a percentage, then `status`. On a terminal the
// line is redrawn in place and `final` ends it; otherwise it is one plain line.
void draw_progress(std::FILE* out, bool terminal, double done, const std::string& status, bool final);

class ProgressLine {
 public:
  static constexpr double kTerminalEvery = 0.2;  // seconds between redraws
  static constexpr double kPlainEvery = 10.0;    // seconds between plain lines

  ProgressLine(std::FILE* out, bool terminal);

  double seconds() const;  // since the line was made
  // Whether a report is due (the pause since the last one is over); counts it as made.
  bool due();
  void draw(double done, const std::string& status, bool final) const { draw_progress(out_, terminal_, done, status, final); }

 private:
  std::FILE* out_;
  bool terminal_;
  std::chrono::steady_clock::time_point start_;
  double last_report_ = 0.0;
};

}  // namespace ballagg
