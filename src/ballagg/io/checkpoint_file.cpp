#include "ballagg/io/checkpoint_file.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "ballagg/io/byte_stream.hpp"
#include "ballagg/io/output_dir.hpp"

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

}  // namespace

std::string encode_checkpoint(const Checkpoint& c) {
  ByteWriter payload;
  payload.put_string(c.program_version);
  payload.put<std::int32_t>(c.dimension);
  payload.put_string(c.engine);
  payload.put_string(c.config_toml);
  payload.put(c.wall_seconds);
  for (const std::string* s : {&c.totals, &c.state, &c.engine_state, &c.timeseries, &c.snapshots}) payload.put_string(*s);
  ByteWriter file;
  const std::string& body = payload.bytes();
  std::string out(kMagic);
  file.put(kCheckpointFormat);
  file.put(kByteOrder);
  file.put<std::uint64_t>(body.size());
  out += file.bytes();
  out += body;
  const std::uint32_t crc = crc_of(body);
  out.append(reinterpret_cast<const char*>(&crc), sizeof crc);
  return out;
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
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::error_code ec;
    if (fs::exists(fs::path(dir) / "summary.json", ec))
      throw CheckpointError(fmt::format("{}: the run has finished (no {} left to resume from)", dir, kCheckpointFile));
    throw CheckpointError(fmt::format("{}: no checkpoint to resume from ({} missing)", dir, kCheckpointFile));
  }
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return decode_checkpoint(bytes, path.string());
}

void write_checkpoint_file(const std::string& dir, const std::string& bytes) {
  const fs::path target = fs::path(dir) / kCheckpointFile;
  const std::string temporary = temporary_path_for(target.string());
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(fmt::format("{}: cannot create: {}", temporary, std::strerror(errno)));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  const bool ok = done == bytes.size() && ::fsync(fd) == 0;
  const int saved_errno = errno;
  ::close(fd);
  if (!ok) {
    std::error_code ec;
    fs::remove(temporary, ec);
    throw std::runtime_error(fmt::format("{}: cannot write the checkpoint: {}", target.string(), std::strerror(saved_errno)));
  }
  rename_into_place(temporary, target.string());
}

}  // namespace ballagg
