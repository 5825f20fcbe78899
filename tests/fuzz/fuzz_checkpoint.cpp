// libFuzzer target: the checkpoint file reader (decode_checkpoint) on whole files, as
// `ballagg run --resume` reads them. Any bytes must give a Checkpoint or one
// CheckpointError. The CRC-32 makes nearly every mutation a "checksum mismatch", so the
// sections behind it are fuzzed by fuzz_checkpoint_sections.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/io/checkpoint_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    ballagg::decode_checkpoint(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.bin");
  } catch (const ballagg::CheckpointError&) {
  }
  return 0;
}
