#pragma once
// A checkpoint file around a bare payload (docs/checkpoints.md): magic, format, byte
// order, size, payload, CRC-32. The fuzz target fuzz_checkpoint_sections mutates payloads
// so that they get past the checksum, and the regression tests replay its findings.
#include <zlib.h>

#include <cstdint>
#include <string>
#include <string_view>

#include "ballagg/core/byte_stream.hpp"
#include "ballagg/io/checkpoint_file.hpp"

namespace ballagg::testing {

inline std::string checkpoint_file_of(std::string_view payload) {
  ByteWriter header;
  header.put(kCheckpointFormat);
  header.put(std::uint32_t{0x01020304});
  header.put(std::uint64_t{payload.size()});
  const auto crc = static_cast<std::uint32_t>(
      crc32_z(0L, reinterpret_cast<const Bytef*>(payload.data()), static_cast<z_size_t>(payload.size())));
  std::string file = std::string("BALLAGG CHECKPT\n", 16) + header.bytes();
  file.append(payload);
  file.append(reinterpret_cast<const char*>(&crc), sizeof crc);
  return file;
}

}  // namespace ballagg::testing
