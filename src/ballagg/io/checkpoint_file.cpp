#include "ballagg/io/checkpoint_file.hpp"

#include <zlib.h>

#include <filesystem>

#include <fmt/format.h>

#include "ballagg/config/text_file.hpp"
#include "ballagg/core/byte_stream.hpp"
#include "ballagg/core/run_guard.hpp"
#include "ballagg/io/atomic_file.hpp"

namespace fs = std::filesystem;

namespace ballagg {
namespace {

constexpr std::string_view kMagic{"BALLAGG CHECKPT\n", 16};
constexpr std::uint32_t kByteOrder = 0x01020304;
constexpr std::size_t kHeaderSize = kMagic.size() + 4 + 4 + 8;
constexpr std::size_t kTrailerSize = 4;

std::uint32_t crc_of(std::string_view bytes) {
  return static_cast<std::uint32_t>(
      crc32_z(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<z_size_t>(bytes.size())));
}

// Hands the file's bytes to out(data, size) piece by piece: the header, the payload's
// fields and sections (never copied into one buffer: a checkpoint of 10^6 spheres is a few
// hundred MB), the CRC of the payload.
template <class Out>
void emit_checkpoint(const Checkpoint& c, Out&& out) {
  ByteWriter fields;  // the small fields before the sections
  fields.put_string(c.program_version);
  fields.put<std::int32_t>(c.dimension);
  fields.put_string(c.engine);
  fields.put_string(c.config_toml);
  fields.put(c.wall_seconds);
  const std::string* sections[] = {&c.totals, &c.state, &c.engine_state, &c.timeseries, &c.snapshots};
  std::uint64_t size = fields.bytes().size();
  for (const std::string* s : sections) size += sizeof(std::uint64_t) + s->size();
  ByteWriter header;
  header.put(kCheckpointFormat);
  header.put(kByteOrder);
  header.put(size);
  out(kMagic.data(), kMagic.size());
  out(header.bytes().data(), header.bytes().size());
  uLong crc = crc32_z(0L, Z_NULL, 0);
  auto payload = [&](const char* data, std::size_t n) {
    crc = crc32_z(crc, reinterpret_cast<const Bytef*>(data), static_cast<z_size_t>(n));
    out(data, n);
  };
  payload(fields.bytes().data(), fields.bytes().size());
  for (const std::string* s : sections) {
    const std::uint64_t n = s->size();
    payload(reinterpret_cast<const char*>(&n), sizeof n);
    payload(s->data(), s->size());
  }
  const auto value = static_cast<std::uint32_t>(crc);
  out(reinterpret_cast<const char*>(&value), sizeof value);
}

}  // namespace

std::string encode_checkpoint(const Checkpoint& c) {
  std::string bytes;
  emit_checkpoint(c, [&](const char* data, std::size_t n) { bytes.append(data, n); });
  return bytes;
}

Checkpoint decode_checkpoint(std::string_view bytes, const std::string& source) {
  auto refuse = [&](const std::string& why) { throw CheckpointError(fmt::format("{}: {}", source, why)); };
  if (bytes.size() < kMagic.size() || bytes.substr(0, kMagic.size()) != kMagic)
    refuse("not a ballagg checkpoint (no checkpoint header)");
  if (bytes.size() < kHeaderSize + kTrailerSize) refuse(fmt::format("truncated ({} bytes, a header alone is {})", bytes.size(), kHeaderSize + kTrailerSize));
  ByteReader header(bytes.substr(kMagic.size(), kHeaderSize - kMagic.size()), source);
  const auto version = header.get<std::uint32_t>("format version");
  const auto order = header.get<std::uint32_t>("byte order");
  const auto size = header.get<std::uint64_t>("payload size");
  if (order != kByteOrder) refuse("written on a machine of another byte order");
  if (version != kCheckpointFormat)
    refuse(fmt::format("checkpoint format {}, this ballagg reads format {} only", version, kCheckpointFormat));
  const std::uint64_t have = bytes.size() - kHeaderSize - kTrailerSize;
  if (size != have)
    refuse(fmt::format("{} ({} bytes of {})", size > have ? "truncated" : "longer than its header says", bytes.size(),
                       size + kHeaderSize + kTrailerSize));
  const std::string_view body = bytes.substr(kHeaderSize, size);
  std::uint32_t crc;
  std::memcpy(&crc, bytes.data() + kHeaderSize + size, sizeof crc);
  if (crc != crc_of(body)) refuse("corrupt (checksum mismatch)");

  ByteReader r(body, source);
  Checkpoint c;
  c.program_version = r.get_string("program version");
  c.dimension = r.get<std::int32_t>("dimension");
  if (c.dimension != 2 && c.dimension != 3) r.fail(fmt::format("dimension {}", c.dimension));
  c.engine = r.get_string("engine");
  c.config_toml = r.get_string("configuration");
  c.wall_seconds = r.get<double>("wall seconds");
  for (std::string* s : {&c.totals, &c.state, &c.engine_state, &c.timeseries, &c.snapshots}) *s = r.get_string("section");
  r.expect_end();
  return c;
}

Checkpoint read_checkpoint_file(const std::string& dir) {
  const fs::path path = fs::path(dir) / kCheckpointFile;
  std::error_code ec;
  if (!fs::exists(path, ec)) {  // a link to nothing included
    if (fs::exists(fs::path(dir) / "summary.json", ec))
      throw CheckpointError(fmt::format("{}: the run has finished (no {} left to resume from)", dir, kCheckpointFile));
    throw CheckpointError(fmt::format("{}: no checkpoint to resume from ({} missing)", dir, kCheckpointFile));
  }
  const std::string bytes = read_text_file(path.string(), "checkpoint", kMaxCheckpointBytes);
  return decode_checkpoint(bytes, path.string());
}

void write_checkpoint_file(const std::string& dir, const Checkpoint& checkpoint) {
  const CriticalWrite not_to_be_cut;  // a forced quit waits for the rename
  AtomicFile file((fs::path(dir) / kCheckpointFile).string());
  emit_checkpoint(checkpoint, [&](const char* data, std::size_t n) { file.write({data, n}); });
  file.sync();
  file.commit();
}

}  // namespace ballagg
