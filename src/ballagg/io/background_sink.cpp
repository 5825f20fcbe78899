#include "ballagg/io/background_sink.hpp"

#include <algorithm>

namespace ballagg {

template <int D>
BackgroundSink<D>::BackgroundSink(std::vector<std::unique_ptr<FrameSink<D>>> sinks, int capacity)
    : sinks_(std::move(sinks)), capacity_(std::max(1, capacity)), thread_([this] { drain(); }) {}

template <int D>
BackgroundSink<D>::~BackgroundSink() {
  stop();
}

template <int D>
void BackgroundSink<D>::drain() {
  while (true) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return !queue_.empty() || closing_; });
    if (queue_.empty()) return;  // closing, nothing left
    Frame<D>& frame = queue_.front();
    lock.unlock();
    try {
      if (!error_)
        for (auto& s : sinks_) s->write(frame);
    } catch (...) {
      lock.lock();
      error_ = std::current_exception();
      lock.unlock();
    }
    lock.lock();
    queue_.pop_front();
    changed_.notify_all();
  }
}

template <int D>
void BackgroundSink<D>::write(const Frame<D>& frame) {
  take(Frame<D>(frame));
}

template <int D>
void BackgroundSink<D>::take(Frame<D>&& frame) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return static_cast<int>(queue_.size()) < capacity_ || error_; });
  if (error_) std::rethrow_exception(error_);
  queue_.push_back(std::move(frame));
  changed_.notify_all();
}

template <int D>
void BackgroundSink<D>::stop() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

template <int D>
void BackgroundSink<D>::finish() {
  stop();
  if (error_) std::rethrow_exception(error_);
  for (auto& s : sinks_) s->finish();
}

template class BackgroundSink<2>;
template class BackgroundSink<3>;

}  // namespace ballagg
