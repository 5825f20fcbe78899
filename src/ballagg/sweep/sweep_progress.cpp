#include "ballagg/sweep/sweep_progress.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>

#include <fmt/format.h>

namespace ballagg {

std::string point_parameters(const SweepSpec& spec, const SweepPoint& point) {
  std::string values;
  for (const SweepSetting* s : point.values) values += fmt::format("{}{} = {}", values.empty() ? "" : ", ", s->key, s->value);
  if (!has_variants(spec)) return values;
  return values.empty() ? point.variant->label : point.variant->label + ": " + values;
}

double estimated_seconds_left(double mean_seconds, long long left, int jobs) {
  if (left <= 0) return 0.0;
  return mean_seconds * static_cast<double>(left) / static_cast<double>(std::clamp<long long>(jobs, 1, left));
}

std::string approximate_duration(double seconds) {
  if (seconds < 1.0) return "under 1 s";
  if (seconds < 90.0) return fmt::format("about {:.0f} s", std::round(seconds));
  if (seconds < 90.0 * 60.0) return fmt::format("about {:.0f} min", std::round(seconds / 60.0));
  return fmt::format("about {:.1f} h", seconds / 3600.0);
}

SweepProgress::SweepProgress(const SweepSpec& spec, std::FILE* out, bool quiet, long long runs, int jobs,
                             std::string process)
    : spec_(spec), out_(out), quiet_(quiet), runs_(runs), jobs_(std::max(1, jobs)), process_(std::move(process)) {}

void SweepProgress::start(long long already_finished) {
  if (quiet_) return;
  fmt::print(out_, "sweep{}: {} runs to do, {} finished already, {} at once\n", process_, runs_, already_finished,
             std::min<long long>(jobs_, std::max<long long>(runs_, 1)));
  std::fflush(out_);
}

std::pair<long long, double> SweepProgress::count(double seconds) {
  ++finished_;
  seconds_ += seconds;
  return {finished_, estimated_seconds_left(seconds_ / static_cast<double>(finished_), runs_ - finished_, jobs_)};
}

void SweepProgress::done(const SweepRun& run, const SweepPoint& point, double seconds) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto [rank, left] = count(seconds);
  if (quiet_) return;
  const std::string estimate = rank < runs_ ? fmt::format(" {} left (estimate);", approximate_duration(left)) : "";
  const std::string parameters = point_parameters(spec_, point);
  fmt::print(out_, "sweep{}: [{}/{}]{} {}{} done\n", process_, rank, runs_, estimate, (std::filesystem::path("runs") / run.name).string(),
             parameters.empty() ? "" : " (" + parameters + ")");
  std::fflush(out_);
}

void SweepProgress::failed(const std::string& run_dir, const std::string& what, double seconds) {
  const std::lock_guard<std::mutex> lock(mutex_);
  count(seconds);
  fmt::print(stderr, "ballagg: sweep: run {} failed: {}\n", run_dir, what);
}

}  // namespace ballagg
