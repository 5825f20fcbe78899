#pragma once
// Binary encoding of the checkpoint file's sections: values of trivially copyable types
// in the machine's byte order (the file's header records it, checkpoint_file.hpp), and
// arrays as a 64-bit length followed by their elements.
//
// ByteReader is meant to be fed anything (a truncated file, a foreign one, a fuzzer's
// bytes): every read is bounds-checked, a length is checked against what is left before
// anything is allocated, and every failure is one CheckpointError naming what was being
// read. It never reads past its buffer and never allocates more than the buffer holds.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"
#include "ballagg/core/vec.hpp"

namespace ballagg {

// Types stored as their bytes: trivially copyable ones, and fixed-size Eigen matrices of
// doubles (Vec<D>, rotations, inertia tensors: plain arrays of doubles; Eigen declares
// copy constructors, so they do not count as trivially copyable).
template <class T>
inline constexpr bool kStoredAsBytes = std::is_trivially_copyable_v<T>;
template <int R, int C, int Options, int MaxR, int MaxC>
inline constexpr bool kStoredAsBytes<Eigen::Matrix<double, R, C, Options, MaxR, MaxC>> =
    R > 0 && C > 0 && sizeof(Eigen::Matrix<double, R, C, Options, MaxR, MaxC>) == R * C * sizeof(double);

// A checkpoint that cannot be used: bad input (exit status 2), with one line saying why.
class CheckpointError : public InputError {
 public:
  using InputError::InputError;
};

// Where a streaming ByteWriter hands its bytes (a checkpoint file): in pieces, in order.
class ByteSink {
 public:
  virtual ~ByteSink() = default;
  virtual void write(std::string_view bytes) = 0;
};

// Collects the bytes in a string (bytes(), take()), or, given a sink, passes them on
// through a buffer of at most kByteWriterBufferBytes (plus one value), so that a section
// of hundreds of MB (an engine's state at 10^6 spheres) is never held whole; flush()
// hands on what the buffer still holds and must be called at the end.
inline constexpr std::size_t kByteWriterBufferBytes = std::size_t{1} << 20;

class ByteWriter {
 public:
  ByteWriter() = default;
  explicit ByteWriter(ByteSink& sink) : sink_(&sink) { bytes_.reserve(kByteWriterBufferBytes); }
  ByteWriter(const ByteWriter&) = delete;
  ByteWriter& operator=(const ByteWriter&) = delete;

  template <class T>
  void put(const T& value) {
    static_assert(kStoredAsBytes<T>);
    append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <class T>
  void put_array(const T* data, std::size_t n) {
    static_assert(kStoredAsBytes<T>);
    put<std::uint64_t>(n);
    append(reinterpret_cast<const char*>(data), n * sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& v) { put_array(v.data(), v.size()); }
  void put_string(std::string_view s) { put_array(s.data(), s.size()); }

  // Bytes put so far (handed on or not).
  std::uint64_t size() const { return handed_on_ + bytes_.size(); }
  // Hands the buffered bytes to the sink (nothing without one).
  void flush() {
    if (sink_ == nullptr || bytes_.empty()) return;
    sink_->write(bytes_);
    handed_on_ += bytes_.size();
    bytes_.clear();
  }

  // Without a sink only.
  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

 private:
  void append(const char* data, std::size_t n) {
    if (sink_ != nullptr && bytes_.size() + n > kByteWriterBufferBytes) {
      flush();
      if (n > kByteWriterBufferBytes) {  // a long array goes to the sink as it is
        sink_->write({data, n});
        handed_on_ += n;
        return;
      }
    }
    bytes_.append(data, n);
  }

  std::string bytes_;
  ByteSink* sink_ = nullptr;
  std::uint64_t handed_on_ = 0;
};

class ByteReader {
 public:
  // `what` names the section in error messages ("checkpoint state", ...).
  ByteReader(std::string_view bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}

  template <class T>
  T get(std::string_view field) {
    static_assert(kStoredAsBytes<T>);
    need(sizeof(T), field);
    T value;
    std::memcpy(static_cast<void*>(&value), bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  // An array of at most max_count elements (a count beyond is refused as corrupt).
  template <class T>
  std::vector<T> get_vector(std::string_view field, std::uint64_t max_count = ~std::uint64_t{0}) {
    const std::uint64_t n = count<T>(field, max_count);
    std::vector<T> v(n);
    if (n > 0) std::memcpy(static_cast<void*>(v.data()), bytes_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
    return v;
  }
  // Reads an array into a container with push_back (SmallVector, ...), emptied first.
  template <class T, class Container>
  void get_into(Container& out, std::string_view field, std::uint64_t max_count = ~std::uint64_t{0}) {
    const std::uint64_t n = count<T>(field, max_count);
    out.clear();
    for (std::uint64_t k = 0; k < n; ++k) {
      T value;
      std::memcpy(static_cast<void*>(&value), bytes_.data() + at_ + k * sizeof(T), sizeof(T));
      out.push_back(value);
    }
    at_ += n * sizeof(T);
  }
  std::string get_string(std::string_view field) {
    const std::uint64_t n = count<char>(field, ~std::uint64_t{0});
    std::string s(bytes_.substr(at_, n));
    at_ += n;
    return s;
  }

  std::size_t remaining() const { return bytes_.size() - at_; }

  // Throws unless every byte was read (a section longer than its reader expects is not
  // the format this program writes).
  void expect_end() const {
    if (at_ != bytes_.size())
      fail(fmt::format("{} unexpected bytes at the end", bytes_.size() - at_));
  }
  [[noreturn]] void fail(std::string_view why) const {
    throw CheckpointError(fmt::format("{}: {} (corrupt or written by another version)", what_, why));
  }

 private:
  void need(std::uint64_t n, std::string_view field) const {
    if (n > bytes_.size() - at_) fail(fmt::format("truncated while reading {}", field));
  }
  template <class T>
  std::uint64_t count(std::string_view field, std::uint64_t max_count) {
    const auto n = get<std::uint64_t>(field);
    if (n > max_count) fail(fmt::format("{} has {} entries, at most {} possible", field, n, max_count));
    if (n > (bytes_.size() - at_) / sizeof(T)) fail(fmt::format("truncated while reading {}", field));
    return n;
  }

  std::string_view bytes_;
  std::size_t at_ = 0;
  std::string what_;
};

}  // namespace ballagg
