#include "ballagg/io/background_writer.hpp"

#include <algorithm>

namespace ballagg {

template <int D>
BackgroundWriter<D>::BackgroundWriter(std::vector<std::unique_ptr<FrameSink<D>>> sinks, int capacity)
    : sinks_(std::move(sinks)) {
  for (int k = 0; k < std::max(1, capacity); ++k) free_.push_back(std::make_unique<FrameSource<D>>());
  thread_ = std::thread([this] { drain(); });
}

template <int D>
BackgroundWriter<D>::~BackgroundWriter() {
  stop();
}

template <int D>
void BackgroundWriter<D>::drain() {
  Frame<D> frame;  // reused: its memory is allocated once
  std::unique_lock lock(mutex_);
  while (true) {
    changed_.wait(lock, [&] { return !queue_.empty() || closing_; });
    if (queue_.empty()) return;  // closing, and nothing left to write
    std::unique_ptr<FrameSource<D>> source = std::move(queue_.front());
    queue_.pop_front();
    const bool failed = error_ != nullptr;
    lock.unlock();
    std::exception_ptr error;
    if (!failed) {
      try {
        assemble_frame(*source, frame);
        for (auto& s : sinks_) s->write(frame);
      } catch (...) {
        error = std::current_exception();
      }
    }
    lock.lock();
    if (error) error_ = error;
    free_.push_back(std::move(source));
    changed_.notify_all();
  }
}

template <int D>
FrameSource<D>& BackgroundWriter<D>::acquire() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return !free_.empty() || error_; });
  if (error_) std::rethrow_exception(error_);
  filling_ = std::move(free_.back());
  free_.pop_back();
  return *filling_;
}

template <int D>
void BackgroundWriter<D>::submit() {
  std::lock_guard lock(mutex_);
  queue_.push_back(std::move(filling_));
  changed_.notify_all();
}

template <int D>
void BackgroundWriter<D>::stop() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

template <int D>
void BackgroundWriter<D>::finish() {
  stop();
  if (error_) std::rethrow_exception(error_);
  for (auto& s : sinks_) s->finish();
}

template class BackgroundWriter<2>;
template class BackgroundWriter<3>;

}  // namespace ballagg
