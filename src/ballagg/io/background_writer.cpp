#include "ballagg/io/background_writer.hpp"

#include <functional>

namespace ballagg {

template <int D>
BackgroundWriter<D>::BackgroundWriter(std::vector<std::unique_ptr<FrameSink<D>>> sinks, std::size_t memory_budget)
    : sinks_(std::move(sinks)), budget_(memory_budget) {
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
    Slot slot = std::move(queue_.front());
    queue_.pop_front();
    writing_ = true;
    const bool failed = error_ != nullptr;
    lock.unlock();
    std::exception_ptr error;
    if (!failed) {
      try {
        bool assembled = false;
        const std::function<const Frame<D>&()> assemble = [&]() -> const Frame<D>& {
          if (!assembled) assemble_frame(*slot.source, frame);
          assembled = true;
          return frame;
        };
        for (auto& s : sinks_) s->write_source(*slot.source, assemble);
      } catch (...) {
        error = std::current_exception();
      }
    }
    slot.source->layout.reset();  // shared with later frames, or back to LayoutCopies' spares
    lock.lock();
    if (error) error_ = error;
    free_.push_back(std::move(slot));
    writing_ = false;
    changed_.notify_all();
  }
}

template <int D>
FrameSource<D>& BackgroundWriter<D>::acquire() {
  std::unique_lock lock(mutex_);
  // A free source; else a new one if the budget allows it or none exists yet; else wait
  // for the writer to free one.
  changed_.wait(lock, [&] { return !free_.empty() || held_ == 0 || held_ + frame_bytes_ <= budget_ || error_; });
  if (error_) std::rethrow_exception(error_);
  if (!free_.empty()) {
    filling_ = std::move(free_.back());
    free_.pop_back();
  } else {
    filling_ = Slot{std::make_unique<FrameSource<D>>(), 0};
    ++sources_;
  }
  return *filling_.source;
}

template <int D>
void BackgroundWriter<D>::submit() {
  std::lock_guard lock(mutex_);
  const std::size_t bytes = filling_.source->bytes();  // capture may have grown it
  held_ = held_ - filling_.bytes + bytes;
  filling_.bytes = bytes;
  frame_bytes_ = bytes;
  queue_.push_back(std::move(filling_));
  changed_.notify_all();
}

template <int D>
int BackgroundWriter<D>::sources() const {
  std::lock_guard lock(mutex_);
  return sources_;
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

template <int D>
std::vector<std::uint64_t> BackgroundWriter<D>::flush() {
  {
    // Nothing queued, nothing being written.
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return (queue_.empty() && !writing_) || error_; });
    if (error_) std::rethrow_exception(error_);
  }
  std::vector<std::uint64_t> marks;
  for (auto& s : sinks_) marks.push_back(s->flush());  // the writer thread is idle
  return marks;
}

template class BackgroundWriter<2>;
template class BackgroundWriter<3>;

}  // namespace ballagg
