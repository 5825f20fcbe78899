#pragma once
// Checkpoints during a run (docs/checkpoints.md): every output.checkpoint_every wall
// seconds, and at SIGINT or SIGTERM, after which the run ends by throwing RunInterrupted
// (the command line prints how to resume and exits with 128 + the signal's number).
#include <chrono>
#include <csignal>
#include <functional>
#include <stdexcept>
#include <string>

#include "ballagg/engines/engine.hpp"
#include "ballagg/io/checkpoint_file.hpp"

namespace ballagg {

// The run was stopped by a signal after a checkpoint was written.
class RunInterrupted : public std::runtime_error {
 public:
  RunInterrupted(int signal, const std::string& message) : std::runtime_error(message), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// While alive, SIGINT and SIGTERM only raise a flag that Checkpointer polls; the previous
// handlers come back at destruction. A second signal of the same kind acts as it would
// have without us (a run that does not reach a checkpoint point can still be stopped).
class InterruptFlag {
 public:
  InterruptFlag();
  ~InterruptFlag();
  InterruptFlag(const InterruptFlag&) = delete;
  InterruptFlag& operator=(const InterruptFlag&) = delete;
  // The signal received, or 0.
  static int received();

 private:
  struct sigaction previous_int_{}, previous_term_{};
};

template <int D>
class Checkpointer final : public RunObserver<D> {
 public:
  // compose(state, engine_state, wall seconds of this segment) gathers the checkpoint.
  using Compose = std::function<Checkpoint(const State<D>&, const std::string&, double)>;
  // every: wall seconds between checkpoints (0: at signals only); `signals`: whether to
  // act on InterruptFlag::received().
  Checkpointer(std::string dir, double every, bool signals, Compose compose);

  bool checkpoint_due() override;
  void on_checkpoint(const State<D>& s, const EngineCounters& c, const std::string& engine_state) override;

  int written() const { return written_; }

 private:
  using clock = std::chrono::steady_clock;
  double seconds() const { return std::chrono::duration<double>(clock::now() - started_).count(); }

  std::string dir_;
  double every_;
  bool signals_;
  Compose compose_;
  clock::time_point started_ = clock::now();
  double next_ = 0.0;
  int written_ = 0;
};

}  // namespace ballagg
