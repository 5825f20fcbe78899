#pragma once
// Text formatted line by line into a buffer that is handed to a sink whenever it holds
// kTextChunkBytes, so that an output file of any length (final.csv of 10^8 spheres is
// about 9 GB) is written through a buffer of bounded size, never assembled in memory.
#include <cstddef>
#include <iterator>
#include <string_view>

#include <fmt/format.h>

#include "ballagg/core/byte_stream.hpp"

namespace ballagg {

inline constexpr std::size_t kTextChunkBytes = std::size_t{1} << 16;

class ChunkedText {
 public:
  explicit ChunkedText(ByteSink& sink) : sink_(sink) {}
  ChunkedText(const ChunkedText&) = delete;
  ChunkedText& operator=(const ChunkedText&) = delete;

  // Where fmt::format_to writes.
  auto out() { return std::back_inserter(buffer_); }
  void push_back(char c) { buffer_.push_back(c); }
  // Called after each line: hands the buffer on once it holds a chunk.
  void end_line() {
    if (buffer_.size() >= kTextChunkBytes) flush();
  }
  // Hands on what the buffer holds; must be called at the end.
  void flush() {
    if (buffer_.size() == 0) return;
    sink_.write({buffer_.data(), buffer_.size()});
    buffer_.clear();
  }

 private:
  ByteSink& sink_;
  fmt::memory_buffer buffer_;
};

// A sink that collects the text in a string (the text forms of the streamed writers).
class StringSink final : public ByteSink {
 public:
  explicit StringSink(std::string& text) : text_(text) {}
  void write(std::string_view bytes) override { text_.append(bytes); }

 private:
  std::string& text_;
};

}  // namespace ballagg
