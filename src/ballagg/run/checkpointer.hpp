#pragma once
// Checkpoints during a run (docs/checkpoints.md): every output.checkpoint_every wall
// seconds, and at SIGINT, SIGTERM or SIGHUP, after which the run ends by throwing
// RunInterrupted (the command line prints how to resume and exits with 128 + the signal's
// number).
#include <chrono>
#include <csignal>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>

#include "ballagg/engines/engine.hpp"
#include "ballagg/io/checkpoint_file.hpp"

namespace ballagg {

// The run was stopped by a signal: after a checkpoint was written, or (a run without
// checkpoints) without its files.
class RunInterrupted : public std::runtime_error {
 public:
  RunInterrupted(int signal, const std::string& message) : std::runtime_error(message), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// While alive, SIGINT, SIGTERM and SIGHUP (a closed terminal) only ask the run to stop
// (request_stop_by_signal: every loop polls it through its RunGuard); the previous
// handlers come back at destruction. A second one of these signals quits at once, as a
// user who presses Ctrl-C again expects of a program that does not stop, but never in the
// middle of writing a checkpoint or an output file (CriticalWrite: it quits when that
// write is complete), and removes the temporary files no checkpoint refers to first.
class InterruptFlag {
 public:
  InterruptFlag();
  ~InterruptFlag();
  InterruptFlag(const InterruptFlag&) = delete;
  InterruptFlag& operator=(const InterruptFlag&) = delete;
  // The signal received, or 0.
  static int received();

 private:
  static constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
  struct sigaction previous_[std::size(kSignals)]{};
};

// "SIGINT", "SIGTERM", "SIGHUP", or "signal N".
std::string signal_name(int signal);

template <int D>
class Checkpointer final : public RunObserver<D> {
 public:
  // compose(wall seconds of this segment) gathers the checkpoint's small sections; the
  // state and the engine's state are streamed into the file.
  using Compose = std::function<Checkpoint(double)>;
  // every: wall seconds between checkpoints (0: at signals only); `signals`: whether to
  // act on a signal (InterruptFlag); guard: the run's (whether a step was cut short).
  Checkpointer(std::string dir, double every, bool signals, Compose compose, const RunGuard* guard = nullptr);

  bool checkpoint_due() override;
  void on_checkpoint_stream(const State<D>& s, const EngineCounters& c,
                            const typename RunObserver<D>::EngineSave& save) override;

  int written() const { return written_; }

 private:
  using clock = std::chrono::steady_clock;
  double seconds() const { return std::chrono::duration<double>(clock::now() - started_).count(); }

  std::string dir_;
  double every_;
  bool signals_;
  Compose compose_;
  const RunGuard* guard_;
  clock::time_point started_ = clock::now();
  double next_ = 0.0;
  int written_ = 0;
};

}  // namespace ballagg
