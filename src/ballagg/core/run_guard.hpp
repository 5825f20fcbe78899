#pragma once
// What every long loop of a run consults to know whether it must stop: the wall-clock
// limit (stop.wall_seconds), a stop requested by a signal (SIGINT, SIGTERM, SIGHUP: the
// handlers live in run/checkpointer.hpp and call request_stop_by_signal), and a stop
// requested by the run's own output (a row or frame cap, docs/hardening.md).
//
// The engines poll it between events or steps, the recorders between rows and frames,
// the time-stepping minimisations between iterations: no loop of a run goes on for long
// without asking. A poll costs a counter increment; every kPollsPerCheck polls it reads the
// clock and the signal flag (about 20 ns).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>

namespace ballagg {

enum class StopCause : std::uint8_t { none, wall_seconds, signal, output_limit };

// The signal that asked the program to stop, process-wide (0: none). Safe to call from a
// signal handler.
void request_stop_by_signal(int signal) noexcept;
int stop_signal() noexcept;
void clear_stop_signal() noexcept;

// While a CriticalWrite is alive (in any thread), a forced quit (a second signal) waits
// until it ends: a checkpoint or an output file is never left half-renamed by a user who
// pressed Ctrl-C twice. Signal handlers call force_quit(signal) for the second signal.
class CriticalWrite {
 public:
  CriticalWrite() noexcept;
  ~CriticalWrite();
  CriticalWrite(const CriticalWrite&) = delete;
  CriticalWrite& operator=(const CriticalWrite&) = delete;
};

// From a signal handler: ends the process by `signal` with its default action, now, or
// when the last CriticalWrite ends. `cleanup` (async-signal-safe) runs just before.
void force_quit(int signal, void (*cleanup)() noexcept) noexcept;

class RunGuard {
 public:
  // Polls between two readings of the clock and the signal flag. The cheapest loop that
  // polls (an event of the event-driven engine, about 0.3 us) then reads the clock every
  // 20 us or so, and a loop whose iterations cost more reads it proportionally less often.
  static constexpr int kPollsPerCheck = 64;
  // Work inside one time step (the minimisations and their rounds) is cut short by a
  // signal only once the signal has waited this long: cutting a step changes the run, so a
  // prompt checkpoint between two steps, which resumes exactly, is preferred; a step that
  // takes longer is cut (the message says the resumed run will differ).
  static constexpr double kStepSignalGraceSeconds = 1.0;

  // The clock of stop.wall_seconds starts now, or at start_clock().
  explicit RunGuard(double wall_seconds = std::numeric_limits<double>::infinity());
  void start_clock() { started_ = clock::now(); }

  // Whether the run must stop: cheap (see kPollsPerCheck). Once true, stays true.
  bool poll() {
    if (cause_ != StopCause::none) return true;
    if (++polls_ < kPollsPerCheck) return false;
    return check();
  }
  // Reads the clock and the signal flag now.
  bool check();
  bool stopped() const { return cause_ != StopCause::none; }
  StopCause cause() const { return cause_; }
  // Asks the run to stop (the recorders' output caps).
  void stop(StopCause cause) {
    if (cause_ == StopCause::none) cause_ = cause;
  }
  double elapsed() const;
  double wall_seconds() const { return wall_seconds_; }

  // For work inside one step, from any thread: whether it must be cut short now (the
  // wall-clock limit passed, or a signal waited kStepSignalGraceSeconds). Reads the clock.
  // A true answer is remembered (step_cut()): the caller then cuts the work.
  bool step_must_end() const;
  bool step_cut() const { return step_cut_.load(std::memory_order_relaxed); }

 private:
  using clock = std::chrono::steady_clock;
  clock::time_point started_ = clock::now();
  double wall_seconds_;
  StopCause cause_ = StopCause::none;
  int polls_ = 0;
  // When a step first saw the pending signal (seconds since started_, negative: not yet).
  mutable std::atomic<double> signal_seen_{-1.0};
  mutable std::atomic<bool> step_cut_{false};
};

}  // namespace ballagg
