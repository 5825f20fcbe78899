#include "ballagg/run/checkpointer.hpp"

#include <fmt/format.h>

#include "ballagg/core/state_codec.hpp"
#include "ballagg/io/checkpoint_file.hpp"
#include "ballagg/io/temporary_files.hpp"

namespace ballagg {
namespace {

extern "C" void on_stop_signal(int signal) {
  if (stop_signal() == 0) request_stop_by_signal(signal);
  else force_quit(signal, remove_unreferenced_temporaries);
}

}  // namespace

InterruptFlag::InterruptFlag() {
  clear_stop_signal();
  struct sigaction action{};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  for (int s : kSignals) sigaddset(&action.sa_mask, s);  // one handler at a time
  for (std::size_t k = 0; k < std::size(kSignals); ++k) sigaction(kSignals[k], &action, &previous_[k]);
}

InterruptFlag::~InterruptFlag() {
  for (std::size_t k = 0; k < std::size(kSignals); ++k) sigaction(kSignals[k], &previous_[k], nullptr);
  clear_stop_signal();
}

int InterruptFlag::received() { return stop_signal(); }

std::string signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return fmt::format("signal {}", signal);
  }
}

template <int D>
Checkpointer<D>::Checkpointer(std::string dir, double every, bool signals, Compose compose, const RunGuard* guard)
    : dir_(std::move(dir)), every_(every), signals_(signals), compose_(std::move(compose)), guard_(guard), next_(every) {}

template <int D>
bool Checkpointer<D>::checkpoint_due() {
  if (signals_ && stop_signal() != 0) return true;
  return every_ > 0.0 && seconds() >= next_;
}

template <int D>
void Checkpointer<D>::on_checkpoint_stream(const State<D>& s, const EngineCounters&,
                                           const typename RunObserver<D>::EngineSave& save) {
  {
    // The trajectories are flushed for the checkpoint, which refers to their temporary
    // files from its rename on (they are no longer registered as unreferenced from their
    // flush): a forced quit waits until then.
    const CriticalWrite whole_checkpoint;
    write_checkpoint_file(dir_, compose_(seconds()), [&](ByteWriter& w) { StateCodec<D>::encode(s, w); }, save);
  }
  ++written_;
  next_ = seconds() + every_;  // the interval runs from the end of a write
  if (const int signal = signals_ ? stop_signal() : 0) {
    const bool cut = guard_ != nullptr && guard_->step_cut();
    throw RunInterrupted(signal, fmt::format("interrupted by {} at t = {}: checkpoint written{}; continue with: ballagg run "
                                             "--resume {}",
                                             signal_name(signal), s.time,
                                             cut ? " (the time step under way was cut short: the resumed run will "
                                                   "differ from an uninterrupted one)"
                                                 : "",
                                             dir_));
  }
}

template class Checkpointer<2>;
template class Checkpointer<3>;

}  // namespace ballagg
