#include "ballagg/io/gsd_writer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <stdexcept>

#include "ballagg/core/version.hpp"
#include "ballagg/io/output_dir.hpp"

namespace ballagg {
namespace {

// The file layer writes its structs as the machine lays them out; readers expect little
// endian (every platform HOOMD runs on).
static_assert(std::endian::native == std::endian::little, "GSD files are little-endian");

constexpr std::uint64_t kMagic = 0x65DF65DF65DF65DFull;
constexpr std::uint32_t version(std::uint32_t major, std::uint32_t minor) { return major << 16 | minor; }
constexpr std::uint32_t kFileLayerVersion = version(2, 0);
constexpr std::uint32_t kHoomdSchemaVersion = version(1, 4);
constexpr std::size_t kHeaderBytes = 256;
constexpr std::size_t kNameBlock = 64;  // the name list is allocated in blocks of this many bytes

// GSD's type codes.
enum class GsdType : std::uint8_t { uint8 = 1, uint32 = 3, uint64 = 4, int8 = 5, int32 = 7, float32 = 9, float64 = 10 };

std::size_t size_of(GsdType t) {
  switch (t) {
    case GsdType::uint8:
    case GsdType::int8: return 1;
    case GsdType::uint32:
    case GsdType::int32:
    case GsdType::float32: return 4;
    case GsdType::uint64:
    case GsdType::float64: return 8;
  }
  return 0;
}

// A chunk of the hoomd schema that ballagg writes: its name, type, N x M shape, and whether
// it is written in every frame (else in frame 0 only).
struct ChunkSpec {
  const char* name;
  GsdType type;
  std::uint64_t n;
  std::uint32_t m;
  bool every_frame;
};

// The chunks, in name-id order (each frame writes its chunks in this order, so that the
// index is sorted by frame, then by id, as file layer 2.0 requires).
std::vector<ChunkSpec> chunk_specs(std::uint64_t n, bool periodic) {
  std::vector<ChunkSpec> specs = {
      {"configuration/step", GsdType::uint64, 1, 1, true},
      {"configuration/dimensions", GsdType::uint8, 1, 1, false},
      {"configuration/box", GsdType::float32, 6, 1, false},
      {"particles/N", GsdType::uint32, 1, 1, false},
      {"particles/types", GsdType::int8, 1, 2, false},
      {"particles/typeid", GsdType::uint32, n, 1, false},
      {"particles/mass", GsdType::float32, n, 1, false},
      {"particles/diameter", GsdType::float32, n, 1, false},
      {"particles/body", GsdType::int32, n, 1, true},
      {"particles/position", GsdType::float32, n, 3, true},
      {"particles/velocity", GsdType::float32, n, 3, true},
      {"particles/image", GsdType::int32, n, 3, true},
      {"log/time", GsdType::float64, 1, 1, true},
      {"log/kinetic_energy", GsdType::float64, 1, 1, true},
      {"log/clusters", GsdType::int32, 1, 1, true},
      {"log/largest_cluster", GsdType::int32, 1, 1, true},
  };
  if (!periodic)
    specs.erase(std::find_if(specs.begin(), specs.end(),
                             [](const ChunkSpec& c) { return std::strcmp(c.name, "particles/image") == 0; }));
  return specs;
}

std::uint64_t chunk_bytes(const ChunkSpec& c) { return c.n * c.m * size_of(c.type); }

// Bytes of frame `frame`'s chunks.
std::uint64_t frame_bytes(const std::vector<ChunkSpec>& specs, std::uint64_t frame) {
  std::uint64_t bytes = 0;
  for (const ChunkSpec& c : specs)
    if (c.every_frame || frame == 0) bytes += chunk_bytes(c);
  return bytes;
}

// The size of the temporary file of a run that wrote `frames` frames.
std::uint64_t data_end(std::uint64_t n, bool periodic, std::uint64_t frames) {
  const std::vector<ChunkSpec> specs = chunk_specs(n, periodic);
  std::uint64_t bytes = kHeaderBytes;
  for (std::uint64_t k = 0; k < std::min<std::uint64_t>(frames, 1); ++k) bytes += frame_bytes(specs, 0);
  if (frames > 1) bytes += (frames - 1) * frame_bytes(specs, 1);
  return bytes;
}

template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

void put_text(std::string& out, const std::string& text, std::size_t width) {
  std::string field = text.substr(0, width - 1);
  field.resize(width, '\0');
  out += field;
}

// The header (struct gsd_header): where the index and the name list are, and what wrote
// the file in which schema.
std::string header(std::uint64_t index_location, std::uint64_t index_entries, std::uint64_t namelist_location,
                   std::uint64_t namelist_blocks) {
  std::string out;
  put(out, kMagic);
  put(out, index_location);
  put(out, index_entries);
  put(out, namelist_location);
  put(out, namelist_blocks);
  put(out, kHoomdSchemaVersion);
  put(out, kFileLayerVersion);
  put_text(out, std::string("ballagg ") + kVersion, 64);
  put_text(out, "hoomd", 64);
  out.resize(kHeaderBytes, '\0');  // reserved
  return out;
}

}  // namespace

template <int D>
GsdWriter<D>::GsdWriter(const std::string& path, const Particles<D>& particles)
    : particles_(particles), file_(path) {
  const std::string h = header(0, 0, 0, 0);  // completed by finish()
  file_.write(h);
  bytes_ = h.size();
}

template <int D>
GsdWriter<D>::GsdWriter(const std::string& path, const Particles<D>& particles, std::uint64_t mark)
    : particles_(particles),
      file_(path, checked_temporary_size(path, data_end(static_cast<std::uint64_t>(particles.size()),
                                                        particles.box.periodic(), mark))) {
  bytes_ = kHeaderBytes;
  for (std::uint64_t k = 0; k < mark; ++k) index_frame(k);
  frames_ = mark;
}

template <int D>
void GsdWriter<D>::index_frame(std::uint64_t frame) {
  const std::vector<ChunkSpec> specs = chunk_specs(static_cast<std::uint64_t>(particles_.size()), particles_.box.periodic());
  for (std::size_t id = 0; id < specs.size(); ++id) {
    const ChunkSpec& c = specs[id];
    if (!c.every_frame && frame != 0) continue;
    IndexEntry e;
    e.frame = frame;
    e.n = c.n;
    e.m = c.m;
    e.location = static_cast<std::int64_t>(bytes_);
    e.id = static_cast<std::uint16_t>(id);
    e.type = static_cast<std::uint8_t>(c.type);
    index_.push_back(e);
    bytes_ += chunk_bytes(c);
  }
}

template <int D>
void GsdWriter<D>::append_frame_data(const Frame<D>& f) {
  const int n = particles_.size();
  const double l = particles_.box.length;
  const bool first = frames_ == 0;
  // In name-id order (chunk_specs).
  put(data_, static_cast<std::uint64_t>(f.step));
  if (first) {
    put(data_, static_cast<std::uint8_t>(D));
    for (const double edge : {l, l, D == 3 ? l : 0.0, 0.0, 0.0, 0.0}) put(data_, static_cast<float>(edge));
    put(data_, static_cast<std::uint32_t>(n));
    data_ += std::string("S\0", 2);
    for (int i = 0; i < n; ++i) put(data_, std::uint32_t{0});
    for (int i = 0; i < n; ++i) put(data_, static_cast<float>(particles_.mass[i]));
    for (int i = 0; i < n; ++i) put(data_, static_cast<float>(2.0 * particles_.radius[i]));
  }
  for (int i = 0; i < n; ++i) put(data_, static_cast<std::int32_t>(f.cluster[i]));
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) put(data_, static_cast<float>(a < D ? f.position[i][a] - 0.5 * l : 0.0));
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) put(data_, static_cast<float>(a < D ? f.velocity[i][a] : 0.0));
  if (particles_.box.periodic())
    for (int i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) put(data_, a < D ? f.image[i][a] : std::int32_t{0});
  put(data_, f.time);
  put(data_, f.kinetic_energy);
  put(data_, static_cast<std::int32_t>(f.n_clusters));
  put(data_, static_cast<std::int32_t>(f.largest_cluster));
}

template <int D>
void GsdWriter<D>::write(const Frame<D>& frame) {
  if (frame.size() != particles_.size() || frame.velocity.size() != frame.position.size() ||
      frame.cluster.size() != frame.position.size() ||
      frame.image.size() != (particles_.box.periodic() ? frame.position.size() : 0))
    throw std::logic_error("GSD frame with a different number of spheres");
  data_.clear();
  append_frame_data(frame);
  const std::uint64_t start = bytes_;
  index_frame(frames_);
  if (bytes_ - start != data_.size()) throw std::logic_error("GSD frame of another size than its index says");
  file_.write(data_);
  ++frames_;
}

template <int D>
void GsdWriter<D>::finish() {
  const std::vector<ChunkSpec> specs = chunk_specs(static_cast<std::uint64_t>(particles_.size()), particles_.box.periodic());
  // The name list: names separated by 0 bytes, an empty name to end it, in 64-byte blocks.
  std::string names;
  for (const ChunkSpec& c : specs) names.append(c.name).push_back('\0');
  names.push_back('\0');
  names.resize((names.size() + kNameBlock - 1) / kNameBlock * kNameBlock, '\0');
  // The index: every entry, and one empty entry that ends it. A reader takes an entry whose
  // frame is not below the number of entries for a damaged one: there is one per chunk.
  std::string index;
  for (const IndexEntry& e : index_) {
    put(index, e.frame);
    put(index, e.n);
    put(index, e.location);
    put(index, e.m);
    put(index, e.id);
    put(index, e.type);
    put(index, e.flags);
  }
  const std::uint64_t entries = index_.size() + 1;
  index.resize(entries * sizeof(IndexEntry), '\0');
  static_assert(sizeof(IndexEntry) == 32, "struct gsd_index_entry is 32 bytes");
  const std::uint64_t namelist_location = bytes_, index_location = bytes_ + names.size();
  file_.write(names);
  file_.write(index);
  file_.write_at(0, header(index_location, entries, namelist_location, names.size() / kNameBlock));
  file_.commit();
}

template <int D>
std::uint64_t GsdWriter<D>::flush() {
  file_.keep();  // every frame went to the file already (no buffer of ours)
  return frames_;
}

template class GsdWriter<2>;
template class GsdWriter<3>;

}  // namespace ballagg
