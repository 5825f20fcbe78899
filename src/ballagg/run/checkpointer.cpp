#include "ballagg/run/checkpointer.hpp"

#include <fmt/format.h>

namespace ballagg {
namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void remember_signal(int signal) { g_signal = signal; }

void install(int signal, struct sigaction& previous) {
  struct sigaction action{};
  action.sa_handler = remember_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;  // the second one acts as if we were not there
  sigaction(signal, &action, &previous);
}

}  // namespace

InterruptFlag::InterruptFlag() {
  g_signal = 0;
  install(SIGINT, previous_int_);
  install(SIGTERM, previous_term_);
}

InterruptFlag::~InterruptFlag() {
  sigaction(SIGINT, &previous_int_, nullptr);
  sigaction(SIGTERM, &previous_term_, nullptr);
  g_signal = 0;
}

int InterruptFlag::received() { return g_signal; }

template <int D>
Checkpointer<D>::Checkpointer(std::string dir, double every, bool signals, Compose compose)
    : dir_(std::move(dir)), every_(every), signals_(signals), compose_(std::move(compose)), next_(every) {}

template <int D>
bool Checkpointer<D>::checkpoint_due() {
  if (signals_ && InterruptFlag::received() != 0) return true;
  return every_ > 0.0 && seconds() >= next_;
}

template <int D>
void Checkpointer<D>::on_checkpoint(const State<D>& s, const EngineCounters&, const std::string& engine_state) {
  write_checkpoint_file(dir_, compose_(s, engine_state, seconds()));
  ++written_;
  next_ = seconds() + every_;  // the interval runs from the end of a write
  if (const int signal = signals_ ? InterruptFlag::received() : 0) {
    throw RunInterrupted(signal, fmt::format("interrupted by {} at t = {}: checkpoint written; continue with: ballagg run --resume {}",
                                             signal == SIGINT ? "SIGINT" : "SIGTERM", s.time, dir_));
  }
}

template class Checkpointer<2>;
template class Checkpointer<3>;

}  // namespace ballagg
