// ByteWriter given a sink hands on the same bytes it would collect, in pieces no larger
// than its buffer (a long array excepted, which goes on as it is), so that a checkpoint
// section of any size is written without being held whole.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ballagg/core/byte_stream.hpp"

namespace ballagg {
namespace {

class RecordingSink final : public ByteSink {
 public:
  void write(std::string_view bytes) override {
    text.append(bytes);
    pieces.push_back(bytes.size());
  }
  std::string text;
  std::vector<std::size_t> pieces;
};

// Many small values across several buffer lengths, a long array, then small values again.
template <class Writer>
void put_sample(Writer& w) {
  for (std::int64_t k = 0; k < 300'000; ++k) w.put(k * 3 + 1);
  std::vector<double> long_array(kByteWriterBufferBytes / sizeof(double) + 17);
  for (std::size_t k = 0; k < long_array.size(); ++k) long_array[k] = 0.5 * static_cast<double>(k);
  w.put_vector(long_array);
  w.put_string("the end");
  w.put(std::int32_t{-7});
}

TEST(ByteWriter, StreamedBytesEqualCollectedOnes) {
  ByteWriter collected;
  put_sample(collected);
  RecordingSink sink;
  ByteWriter streamed(sink);
  put_sample(streamed);
  EXPECT_EQ(streamed.size(), collected.bytes().size());
  streamed.flush();
  EXPECT_EQ(sink.text, collected.bytes());
  EXPECT_EQ(streamed.size(), collected.bytes().size());
  ASSERT_GE(sink.pieces.size(), 4u);
  // The long array is the only piece beyond the buffer's length.
  EXPECT_EQ(std::count_if(sink.pieces.begin(), sink.pieces.end(), [](std::size_t n) { return n > kByteWriterBufferBytes; }),
            1);
}

TEST(ByteWriter, HandsNothingOnBeforeItsBufferIsFullOrFlushed) {
  RecordingSink sink;
  ByteWriter w(sink);
  w.put(1.0);
  w.put_string("abc");
  EXPECT_TRUE(sink.text.empty());
  w.flush();
  EXPECT_EQ(sink.text.size(), sizeof(double) + sizeof(std::uint64_t) + 3);
  w.flush();  // nothing more
  EXPECT_EQ(sink.pieces.size(), 1u);
}

}  // namespace
}  // namespace ballagg
