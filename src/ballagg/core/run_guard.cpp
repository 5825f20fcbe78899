#include "ballagg/core/run_guard.hpp"

#include <csignal>

namespace ballagg {
namespace {

// Lock-free atomics are safe in signal handlers (std::atomic<int> is on every target).
std::atomic<int> g_stop_signal{0};
std::atomic<int> g_critical_writes{0};
std::atomic<int> g_forced_signal{0};
std::atomic<void (*)() noexcept> g_forced_cleanup{nullptr};
static_assert(std::atomic<int>::is_always_lock_free);
static_assert(std::atomic<double>::is_always_lock_free);

[[noreturn]] void quit_now(int signal, void (*cleanup)() noexcept) noexcept {
  if (cleanup != nullptr) cleanup();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
  std::_Exit(128 + signal);  // the default action of these signals ends the process before
}

}  // namespace

void request_stop_by_signal(int signal) noexcept { g_stop_signal.store(signal, std::memory_order_relaxed); }
int stop_signal() noexcept { return g_stop_signal.load(std::memory_order_relaxed); }
void clear_stop_signal() noexcept { g_stop_signal.store(0, std::memory_order_relaxed); }

CriticalWrite::CriticalWrite() noexcept { g_critical_writes.fetch_add(1); }

CriticalWrite::~CriticalWrite() {
  if (g_critical_writes.fetch_sub(1) != 1) return;
  if (const int signal = g_forced_signal.load()) quit_now(signal, g_forced_cleanup.load());
}

void force_quit(int signal, void (*cleanup)() noexcept) noexcept {
  g_forced_cleanup.store(cleanup);
  g_forced_signal.store(signal);
  if (g_critical_writes.load() == 0) quit_now(signal, cleanup);
  // Else the last CriticalWrite to end quits.
}

RunGuard::RunGuard(double wall_seconds) : wall_seconds_(wall_seconds) {}

double RunGuard::elapsed() const { return std::chrono::duration<double>(clock::now() - started_).count(); }

bool RunGuard::check() {
  polls_ = 0;
  if (cause_ != StopCause::none) return true;
  if (stop_signal() != 0) cause_ = StopCause::signal;
  else if (elapsed() >= wall_seconds_) cause_ = StopCause::wall_seconds;
  return cause_ != StopCause::none;
}

bool RunGuard::step_must_end() const {
  const double now = elapsed();
  bool end = now >= wall_seconds_;
  if (!end && stop_signal() != 0) {
    double seen = signal_seen_.load(std::memory_order_relaxed);
    if (seen < 0.0 && signal_seen_.compare_exchange_strong(seen, now)) seen = now;
    end = now - seen >= kStepSignalGraceSeconds;
  }
  if (end) step_cut_.store(true, std::memory_order_relaxed);
  return end;
}

}  // namespace ballagg
