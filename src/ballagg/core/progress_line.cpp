#include "ballagg/core/progress_line.hpp"

#include <fmt/format.h>

namespace ballagg {

void draw_progress(std::FILE* out, bool terminal, double done, const std::string& status, bool final) {
  if (terminal) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(done * kWidth);
    fmt::print(out, "\r[{}{}] {:3.0f}%  {}\x1b[K{}", std::string(filled, '#'), std::string(kWidth - filled, '.'),
               100.0 * done, status, final ? "\n" : "");
  } else {
    fmt::print(out, "{:3.0f}%  {}\n", 100.0 * done, status);
  }
  std::fflush(out);
}

ProgressLine::ProgressLine(std::FILE* out, bool terminal)
    : out_(out), terminal_(terminal), start_(std::chrono::steady_clock::now()) {}

double ProgressLine::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

bool ProgressLine::due() {
  const double now = seconds();
  if (now - last_report_ < (terminal_ ? kTerminalEvery : kPlainEvery)) return false;
  last_report_ = now;
  return true;
}

}  // namespace ballagg
