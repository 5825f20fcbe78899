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

static_assert(sizeof(z_off_t) >= sizeof(std::uint64_t), "crc32_combine must take section lengths of 64 bits");

std::string_view bytes_of(const std::uint64_t& value) { return {reinterpret_cast<const char*>(&value), sizeof value}; }

// One section of the payload: its bytes, or the writer that puts them.
struct Section {
  std::string_view bytes;
  const SectionWriter* writer = nullptr;
};

// Hands the file's bytes to `out` (write(bytes) in order, write_at(offset, bytes) over
// bytes already written) piece by piece: the header, the payload's fields and sections
// (never copied into one buffer: a checkpoint of 10^6 spheres is a few hundred MB), the
// CRC of the payload. A length not known before its bytes are put (the payload's, a
// streamed section's) is written as zeros and filled in once known; the CRC is combined
// from those of the pieces around it (crc32_combine), so the bytes are the same either way.
template <class Out>
class CheckpointEmitter final : public ByteSink {
 public:
  explicit CheckpointEmitter(Out& out) : out_(out) {}

  void header() {
    ByteWriter h;
    h.put(kCheckpointFormat);
    h.put(kByteOrder);
    h.put(std::uint64_t{0});  // the payload's size, filled in by finish()
    out_.write(kMagic);
    out_.write(h.bytes());
    at_ = kHeaderSize;
  }
  // Payload bytes.
  void write(std::string_view bytes) override {
    crc_ = crc32_z(crc_, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<z_size_t>(bytes.size()));
    out_.write(bytes);
    at_ += bytes.size();
  }
  void section(const Section& s) {
    if (s.writer == nullptr) {
      write(bytes_of(s.bytes.size()));
      write(s.bytes);
      return;
    }
    const std::uint64_t length_at = at_;
    const uLong crc_before = crc_;
    out_.write(bytes_of(0));
    at_ += sizeof(std::uint64_t);
    crc_ = crc32_z(0L, Z_NULL, 0);
    ByteWriter w(*this);
    (*s.writer)(w);
    w.flush();
    const std::uint64_t n = w.size();
    out_.write_at(length_at, bytes_of(n));
    const uLong crc_length = crc32_z(0L, reinterpret_cast<const Bytef*>(&n), sizeof n);
    crc_ = crc32_combine(crc32_combine(crc_before, crc_length, sizeof n), crc_, static_cast<z_off_t>(n));
  }
  void finish() {
    out_.write_at(kMagic.size() + 2 * sizeof(std::uint32_t), bytes_of(at_ - kHeaderSize));
    const auto value = static_cast<std::uint32_t>(crc_);
    out_.write({reinterpret_cast<const char*>(&value), sizeof value});
  }

 private:
  Out& out_;
  std::uint64_t at_ = 0;
  uLong crc_ = crc32_z(0L, Z_NULL, 0);
};

template <class Out>
void emit_checkpoint(const Checkpoint& c, const Section (&sections)[5], Out& out) {
  ByteWriter fields;  // the small fields before the sections
  fields.put_string(c.program_version);
  fields.put<std::int32_t>(c.dimension);
  fields.put_string(c.engine);
  fields.put_string(c.config_toml);
  fields.put(c.wall_seconds);
  CheckpointEmitter<Out> emit(out);
  emit.header();
  emit.write(fields.bytes());
  for (const Section& s : sections) emit.section(s);
  emit.finish();
}

// encode_checkpoint's destination.
struct StringOut {
  std::string& bytes;
  void write(std::string_view b) { bytes.append(b); }
  void write_at(std::uint64_t offset, std::string_view b) { bytes.replace(offset, b.size(), b); }
};

void write_file(const std::string& dir, const Checkpoint& c, const Section (&sections)[5]) {
  const CriticalWrite not_to_be_cut;  // a forced quit waits for the rename
  AtomicFile file((fs::path(dir) / kCheckpointFile).string());
  emit_checkpoint(c, sections, file);
  file.sync();
  file.commit();
}

}  // namespace

std::string encode_checkpoint(const Checkpoint& c) {
  std::string bytes;
  StringOut out{bytes};
  emit_checkpoint(c, {{c.totals}, {c.state}, {c.engine_state}, {c.timeseries}, {c.snapshots}}, out);
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

void write_checkpoint_file(const std::string& dir, const Checkpoint& c) {
  write_file(dir, c, {{c.totals}, {c.state}, {c.engine_state}, {c.timeseries}, {c.snapshots}});
}

void write_checkpoint_file(const std::string& dir, const Checkpoint& c, const SectionWriter& state,
                           const SectionWriter& engine_state) {
  write_file(dir, c, {{c.totals}, {{}, &state}, {{}, &engine_state}, {c.timeseries}, {c.snapshots}});
}

}  // namespace ballagg
