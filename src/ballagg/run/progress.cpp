#include "ballagg/run/progress.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "ballagg/core/progress_line.hpp"

namespace ballagg {

template <int D>
double ProgressReporter<D>::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

template <int D>
void ProgressReporter<D>::on_start(const State<D>& s) {
  start_ = std::chrono::steady_clock::now();
  initial_clusters_ = s.n_clusters();
}

template <int D>
void ProgressReporter<D>::after_event(const State<D>& s, const EventRecord&, const EngineCounters& c) {
  if (c.events % 1024 != 0) return;
  const double now = seconds();
  if (now - last_report_ < (terminal_ ? kTerminalEvery : kPlainEvery)) return;
  last_report_ = now;
  report(s, c.events, Moment::running);
}

template <int D>
void ProgressReporter<D>::on_finish(const State<D>& s, const RunResult& r) {
  // A run that reached an end of its own is done, whichever criterion ended it; one cut by
  // the wall clock, the output limit or a signal shows how far it got.
  const bool cut = r.reason == StopReason::wall_seconds || r.reason == StopReason::output_limit ||
                   r.reason == StopReason::interrupted;
  report(s, r.counters.events, cut ? Moment::cut : Moment::ended);
}

template <int D>
void ProgressReporter<D>::report(const State<D>& s, std::int64_t events, Moment moment) {
  // Fraction done: of stop.time when it is set, the one target whose progress is linear in
  // its measure (clusters vanish fast early and slowly late: model (v) removes half of
  // them by t = 2.25 of its 40.8); otherwise of the clusters to remove. A run that another
  // criterion ends first jumps to 100% when it ends.
  double done = 0.0;
  if (std::isfinite(stop_.time)) {
    done = std::clamp(s.time / stop_.time, 0.0, 1.0);
  } else {
    const double to_remove = std::max(1, initial_clusters_ - static_cast<int>(stop_.clusters));
    done = std::clamp((initial_clusters_ - s.n_clusters()) / to_remove, 0.0, 1.0);
  }
  if (moment == Moment::running) done = std::min(done, 0.99);  // "100%" only once the run has ended
  if (moment == Moment::ended) done = 1.0;
  const bool final = moment != Moment::running;
  const double elapsed = seconds();
  const double rate = elapsed > 0.0 ? events / elapsed : 0.0;
  const std::string status = fmt::format("clusters {} / {}  t = {:.6g}  {:.3g} M events/s  {:.1f} s", s.n_clusters(),
                                         s.n_spheres(), s.time, rate * 1e-6, elapsed);
  draw_progress(out_, terminal_, done, status, final);
}

template class ProgressReporter<2>;
template class ProgressReporter<3>;

}  // namespace ballagg
