#include "ballagg/io/h5md_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "ballagg/config/config.hpp"
#include "ballagg/core/version.hpp"
#include "ballagg/io/hdf5_handle.hpp"
#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/output_error.hpp"
#include "ballagg/io/temporary_files.hpp"

namespace ballagg {

namespace {

using hdf5::check;
using hdf5::Handle;
using hdf5::Series;

// At most this many spheres per chunk of every per-sphere dataset (and per block written):
// chunks of up to 256 KB (cluster ids) to 1.5 MB (positions, doubles in 3D), large enough
// for fast writes, small enough that reading one sphere's history does not read whole
// frames and that a block of every dataset stays in the cache between its assembly and its
// write. The N spheres are cut into equal chunks (chunk_spheres): a last chunk mostly
// beyond N would be written whole all the same, padding every frame of every dataset.
constexpr int kMaxChunkSpheres = 1 << 16;

int chunk_spheres(int n) {
  const int chunks = std::max(1, (n + kMaxChunkSpheres - 1) / kMaxChunkSpheres);
  return std::max(1, (n + chunks - 1) / chunks);
}
constexpr hsize_t kScalarChunk = 1024;  // records per chunk of step, time and observables

// The unit attributes of the 3D layout. ballagg's quantities are dimensionless (lengths in
// the unit of system.radius, times in length / speed), and H5MD readers that map unit
// strings accept only physical ones: these are MDAnalysis's own base units, so that
// MDAnalysis reads the numbers unchanged (it converts every other unit it knows). No H5MD
// units module is declared (h5md/modules), so an H5MD reader takes them as extra attributes.
constexpr const char* kLengthUnit = "Angstrom";
constexpr const char* kTimeUnit = "ps";
constexpr const char* kVelocityUnit = "Angstrom ps-1";

// Bytes of frames after which the written pages are put on disk and dropped from the page
// cache (release_written_pages).
constexpr std::size_t kReleasePagesBytes = std::size_t{32} << 20;

// Runs `write`, a step of writing the file `target`: a failure inside HDF5 (which does not
// pass on errno; with a valid file, the disk) becomes one OutputError naming the file.
template <class F>
auto writing(const std::filesystem::path& target, F&& write) {
  try {
    return write();
  } catch (const InputError&) {
    throw;
  } catch (const OutputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw OutputError(fmt::format("{}: cannot write: {} (disk full?)", target.string(), e.what()));
  }
}

// One block of per-sphere values, as stored (Real: the precision of positions and velocities).
template <int D, class Real>
struct Block {
  std::vector<Real> position, velocity;
  std::vector<std::int32_t> image, cluster;
  void reserve(int spheres, bool periodic) {
    position.resize(static_cast<std::size_t>(spheres) * D);
    velocity.resize(static_cast<std::size_t>(spheres) * D);
    image.resize(periodic ? static_cast<std::size_t>(spheres) * D : 0);
    cluster.resize(static_cast<std::size_t>(spheres));
  }
};

}  // namespace

template <int D>
struct H5mdWriter<D>::Impl {
  std::filesystem::path target, temporary;
  Handle file;
  int n = 0;
  bool periodic = false;
  // Dimensions stored per sphere: D, or 3 for a 2D run padded with z = 0. A file stored in
  // 3D has the layout 3D readers need: unit attributes and the box per frame (edges).
  int stored = D;
  std::array<double, 9> edge_matrix{};  // the box as rows of edge vectors (stored = 3)
  SnapshotPrecision precision = SnapshotPrecision::single;
  bool keep = false;  // a checkpoint refers to the temporary file
  UnreferencedTemporary registered;  // until kept or renamed: a forced quit removes it
  std::unique_ptr<Series> step, time, edges, position, image, velocity, cluster, clusters, largest, energy;
  std::size_t unreleased_bytes = 0;  // frame data written since the last release_written_pages
  Block<D, float> single_block;
  Block<D, double> double_block;
  FrameAssembler<D> assembler;
  std::vector<float> padded_single;  // a block's positions or velocities in 3D (stored = 3, D = 2)
  std::vector<double> padded_double;
  std::vector<std::int32_t> padded_image;

  // The file type of positions and velocities (also the type of the blocks in memory).
  hid_t real_type() const { return precision == SnapshotPrecision::single ? H5T_NATIVE_FLOAT : H5T_NATIVE_DOUBLE; }

  Impl(const std::string& path, const Particles<D>& p, const std::string& config_toml, SnapshotPrecision real,
       bool pad_3d)
      : precision(real) {
    set_stored(p, pad_3d);
    hdf5::quiet_errors();
    target = path;
    temporary = fresh_temporary_for(path);
    registered.hold(temporary.string());
    try {
      create(p, config_toml);
    } catch (...) {
      discard();
      throw;
    }
  }

  // The stored dimension and box: a 2D run padded to 3D gets a third edge one largest
  // diameter deep (final.xyz's slab), not periodic.
  void set_stored(const Particles<D>& p, bool pad_3d) {
    stored = D == 3 || pad_3d ? 3 : D;
    if (stored != 3) return;
    const double depth = D == 3 ? p.box.length : 2.0 * *std::max_element(p.radius.begin(), p.radius.end());
    edge_matrix = {p.box.length, 0.0, 0.0, 0.0, p.box.length, 0.0, 0.0, 0.0, depth};
  }

  // The file, then its groups in a fixed order (the bytes of the file depend on it): h5md,
  // particles/all with the box and the fixed per-sphere data, the time series, the
  // observables, the parameters.
  void create(const Particles<D>& p, const std::string& config_toml) {
    n = p.size();
    periodic = p.box.periodic();
    create_file();
    write_h5md_group(file);
    const Handle particles = hdf5::create_group(file, "particles");
    const Handle all = hdf5::create_group(particles, "all");
    const Handle box = write_box(all, p);
    hdf5::write_dataset(all, "radius", p.radius);
    hdf5::write_dataset(all, "mass", p.mass);
    const Handle g_position = hdf5::create_group(all, "position");
    create_particle_series(all, box, g_position);
    create_observables(g_position);
    const Handle parameters = hdf5::create_group(file, "parameters");
    hdf5::write_string_dataset(parameters, "config.toml", config_toml);
    hdf5::write_string_dataset(parameters, "ballagg_version", kVersion);
    // A 2D run stored in 3D says so (H5mdReader reads it back in 2D).
    if (stored != D) hdf5::write_attribute(parameters, "dimension", std::vector<std::int32_t>{D});
  }

  void create_file() {
    // The H5MD-recommended file format version 2, readable by HDF5 1.8 and later.
    const Handle fapl(check(H5Pcreate(H5P_FILE_ACCESS), "file properties"), H5Pclose);
    check(H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_V18), "file properties");
    // No timestamps on the root group either (the file creation list is a group's).
    const Handle fcpl(check(H5Pcreate(H5P_FILE_CREATE), "file properties"), H5Pclose);
    check(H5Pset_obj_track_times(fcpl, false), "file properties");
    file = Handle(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, fcpl, fapl), H5Fclose);
    if (file.get() < 0) {
      H5Eclear2(H5E_DEFAULT);
      throw std::runtime_error("cannot create the file");
    }
  }

  static void write_h5md_group(hid_t root) {
    const Handle h5md = hdf5::create_group(root, "h5md");
    hdf5::write_attribute(h5md, "version", std::vector<std::int32_t>{1, 1});
    // H5MD asks for an author; ballagg does not record who ran it, so the file is the
    // same whoever runs it.
    hdf5::write_attribute(hdf5::create_group(h5md, "author"), "name", std::string("unknown"));
    const Handle creator = hdf5::create_group(h5md, "creator");
    hdf5::write_attribute(creator, "name", std::string("ballagg"));
    hdf5::write_attribute(creator, "version", std::string(kVersion));
  }

  // The box group: its dimension and boundaries, and (stored in D < 3) its fixed edges; in
  // 3D the edges are a time series (create_particle_series).
  Handle write_box(hid_t all, const Particles<D>& p) const {
    Handle box = hdf5::create_group(all, "box");
    hdf5::write_attribute(box, "dimension", std::vector<std::int32_t>{stored});
    std::vector<std::string> boundary(D, periodic ? "periodic" : "none");
    boundary.resize(stored, "none");
    hdf5::write_attribute(box, "boundary", boundary);
    if (stored != 3) hdf5::write_dataset(box, "edges", std::vector<double>(D, p.box.length));
    return box;
  }

  // A time-dependent group `name` of `parent` that shares the positions' step and time.
  static Handle time_dependent_group(hid_t g_position, hid_t parent, const std::string& name) {
    Handle g = hdf5::create_group(parent, name);
    check(H5Lcreate_hard(g_position, "step", g, "step", H5P_DEFAULT, H5P_DEFAULT), name + "/step");
    check(H5Lcreate_hard(g_position, "time", g, "time", H5P_DEFAULT, H5P_DEFAULT), name + "/time");
    return g;
  }

  // step, time and the per-sphere series (position, box edges in 3D, image, velocity,
  // cluster), with the unit attributes of the 3D layout.
  void create_particle_series(hid_t all, hid_t box, hid_t g_position) {
    const hsize_t un = static_cast<hsize_t>(n);
    const hsize_t rows = static_cast<hsize_t>(chunk_spheres(n));
    const hsize_t s = static_cast<hsize_t>(stored);
    const bool layout_3d = stored == 3;
    step = std::make_unique<Series>(g_position, "step", H5T_NATIVE_INT64, std::vector<hsize_t>{}, kScalarChunk,
                                    Series::Compression::none);
    time = std::make_unique<Series>(g_position, "time", H5T_NATIVE_DOUBLE, std::vector<hsize_t>{}, kScalarChunk,
                                    Series::Compression::none);
    position = std::make_unique<Series>(g_position, "value", real_type(), std::vector<hsize_t>{un, s}, rows,
                                        Series::Compression::none);
    auto element = [&](hid_t parent, const std::string& name) { return time_dependent_group(g_position, parent, name); };
    if (layout_3d) {
      // The box per frame, as a matrix of edge vectors: MDAnalysis reads no other form.
      edges = std::make_unique<Series>(element(box, "edges"), "value", H5T_NATIVE_DOUBLE, std::vector<hsize_t>{s, s},
                                       s, Series::Compression::none);
      hdf5::write_variable_string_attribute(edges->id(), "unit", kLengthUnit);
      hdf5::write_variable_string_attribute(position->id(), "unit", kLengthUnit);
      hdf5::write_variable_string_attribute(time->id(), "unit", kTimeUnit);
    }
    if (periodic)
      image = std::make_unique<Series>(element(all, "image"), "value", H5T_NATIVE_INT32, std::vector<hsize_t>{un, s},
                                       rows, Series::Compression::shuffle_deflate);
    velocity = std::make_unique<Series>(element(all, "velocity"), "value", real_type(), std::vector<hsize_t>{un, s},
                                        rows, Series::Compression::none);
    if (layout_3d) hdf5::write_variable_string_attribute(velocity->id(), "unit", kVelocityUnit);
    cluster = std::make_unique<Series>(element(all, "cluster"), "value", H5T_NATIVE_INT32, std::vector<hsize_t>{un},
                                       rows, Series::Compression::none);
  }

  void create_observables(hid_t g_position) {
    const Handle observables = hdf5::create_group(file, "observables");
    auto scalar = [&](const char* name, hid_t type) {
      return std::make_unique<Series>(time_dependent_group(g_position, observables, name), "value", type,
                                      std::vector<hsize_t>{}, kScalarChunk, Series::Compression::none);
    };
    clusters = scalar("clusters", H5T_NATIVE_INT32);
    largest = scalar("largest_cluster", H5T_NATIVE_INT32);
    energy = scalar("kinetic_energy", H5T_NATIVE_DOUBLE);
  }

  // Reopens the temporary file of a checkpointed run at `frames` frames.
  Impl(const std::string& path, const Particles<D>& p, std::uint64_t frames, SnapshotPrecision real, bool pad_3d)
      : precision(real), keep(true) {
    set_stored(p, pad_3d);
    hdf5::quiet_errors();
    target = path;
    temporary = temporary_path_for(path);
    n = p.size();
    periodic = p.box.periodic();
    check_output_path(path);
    reclaim_completed_file(path);  // killed between completing the trajectory and finishing
    std::error_code ec;
    if (!std::filesystem::is_regular_file(std::filesystem::symlink_status(temporary, ec)))
      throw InputError(fmt::format("{}: the trajectory of the checkpointed run is {} (cannot resume it)",
                                   temporary.string(), std::filesystem::exists(std::filesystem::symlink_status(temporary, ec))
                                                           ? "not a regular file" : "missing"));
    try {
      reopen(frames);
    } catch (const std::runtime_error& e) {
      close_datasets();
      file.reset();
      throw InputError(fmt::format("{}: cannot continue the trajectory of the checkpointed run ({})",
                                   temporary.string(), e.what()));
    }
  }

  void reopen(hsize_t frames) {
    file = Handle(H5Fopen(temporary.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    if (file.get() < 0) throw std::runtime_error("not a readable HDF5 file");
    const hsize_t un = static_cast<hsize_t>(n), s = static_cast<hsize_t>(stored);
    auto series = [&](const std::string& path, hid_t type, std::vector<hsize_t> inner) {
      return std::make_unique<Series>(file, path, type, std::move(inner), frames);
    };
    step = series("particles/all/position/step", H5T_NATIVE_INT64, {});
    time = series("particles/all/position/time", H5T_NATIVE_DOUBLE, {});
    if (stored == 3) edges = series("particles/all/box/edges/value", H5T_NATIVE_DOUBLE, {s, s});
    position = series("particles/all/position/value", real_type(), {un, s});
    if (periodic) image = series("particles/all/image/value", H5T_NATIVE_INT32, {un, s});
    velocity = series("particles/all/velocity/value", real_type(), {un, s});
    cluster = series("particles/all/cluster/value", H5T_NATIVE_INT32, {un});
    clusters = series("observables/clusters/value", H5T_NATIVE_INT32, {});
    largest = series("observables/largest_cluster/value", H5T_NATIVE_INT32, {});
    energy = series("observables/kinetic_energy/value", H5T_NATIVE_DOUBLE, {});
  }

  std::uint64_t flush() {
    check(H5Fflush(file, H5F_SCOPE_GLOBAL), "flush");
    keep = true;
    registered.release();
    return step->records();
  }

  ~Impl() {
    if (file.get() < 0) return;
    if (!keep) {
      discard();
      return;
    }
    close_datasets();  // the checkpoint's file stays, closed cleanly
    file.reset();
  }

  void close_datasets() {
    for (auto* s : {&step, &time, &edges, &position, &image, &velocity, &cluster, &clusters, &largest, &energy})
      s->reset();
  }

  // Leaves nothing behind (an error, or a run that did not finish).
  void discard() {
    close_datasets();
    file.reset();
    std::error_code ec;
    std::filesystem::remove(temporary, ec);
  }

  // A frame: the scalars, then the per-sphere values block by block, `fill(begin, end,
  // block)` putting spheres [begin, end) in the block.
  template <class Real, class Fill>
  void write_frame(std::int64_t frame_step, double frame_time, const std::int32_t (&counts)[2], double kinetic_energy,
                   Block<D, Real>& block, Fill&& fill) {
    step->append(&frame_step);
    time->append(&frame_time);
    if (edges) edges->append(edge_matrix.data());
    position->add_record();
    if (image) image->add_record();
    velocity->add_record();
    cluster->add_record();
    const int rows = chunk_spheres(n);
    if (block.cluster.empty()) block.reserve(rows, periodic);
    for (int begin = 0; begin < n; begin += rows) {
      const int end = std::min(n, begin + rows);
      fill(begin, end, block);
      const hsize_t first = static_cast<hsize_t>(begin), count = static_cast<hsize_t>(end - begin);
      const int spheres = end - begin;
      position->write_rows(first, count, in_stored_dimensions(block.position, spheres));
      if (image) image->write_rows(first, count, in_stored_dimensions(block.image, spheres));
      velocity->write_rows(first, count, in_stored_dimensions(block.velocity, spheres));
      cluster->write_rows(first, count, block.cluster.data());
    }
    clusters->append(&counts[0]);
    largest->append(&counts[1]);
    energy->append(&kinetic_energy);
    unreleased_bytes += static_cast<std::size_t>(n) * (2 * D * sizeof(Real) + sizeof(std::int32_t));
    if (unreleased_bytes >= kReleasePagesBytes) release_written_pages();
  }

  // The first `spheres` vectors of a block (D values each) as stored: themselves, or padded
  // with z = 0 into a buffer of 3 per sphere.
  template <class T>
  const T* in_stored_dimensions(const std::vector<T>& values, int spheres) {
    if (stored == D) return values.data();
    std::vector<T>& out = padded_buffer<T>();
    out.assign(static_cast<std::size_t>(spheres) * 3, T{0});
    for (int i = 0; i < spheres; ++i)
      for (int a = 0; a < D; ++a) out[static_cast<std::size_t>(i) * 3 + a] = values[static_cast<std::size_t>(i) * D + a];
    return out.data();
  }
  template <class T>
  std::vector<T>& padded_buffer() {
    if constexpr (std::is_same_v<T, float>) return padded_single;
    else if constexpr (std::is_same_v<T, double>) return padded_double;
    else return padded_image;
  }

  template <class Real>
  void write_assembled(const Frame<D>& f, Block<D, Real>& block) {
    const std::int32_t counts[2] = {f.n_clusters, f.largest_cluster};
    write_frame(f.step, f.time, counts, f.kinetic_energy, block, [&](int begin, int end, Block<D, Real>& b) {
      for (int i = begin; i < end; ++i) {
        const std::size_t at = static_cast<std::size_t>(i - begin) * D;
        for (int a = 0; a < D; ++a) {
          b.position[at + a] = static_cast<Real>(f.position[i][a]);
          b.velocity[at + a] = static_cast<Real>(f.velocity[i][a]);
          if (periodic) b.image[at + a] = f.image[i][a];
        }
        b.cluster[i - begin] = f.cluster[i];
      }
    });
  }

  template <class Real>
  void write_source(const FrameSource<D>& src, Block<D, Real>& block) {
    const std::int32_t counts[2] = {src.n_clusters, src.largest_cluster};
    assembler.start(src);
    write_frame(src.step, src.time, counts, src.kinetic_energy, block, [&](int begin, int end, Block<D, Real>& b) {
      assembler.assemble(begin, end, b.position.data(), b.velocity.data(), periodic ? b.image.data() : nullptr,
                         b.cluster.data());
    });
  }

  void write(const Frame<D>& f) {
    if (f.size() != n || f.velocity.size() != f.position.size() || f.cluster.size() != f.position.size() ||
        f.image.size() != (periodic ? f.position.size() : 0))
      throw std::logic_error("H5MD frame with a different number of spheres");
    if (precision == SnapshotPrecision::single) write_assembled(f, single_block);
    else write_assembled(f, double_block);
  }

  void write(const FrameSource<D>& src) {
    if (src.size() != n || src.layout->offset.size() != src.layout->cluster.size() || src.box.periodic() != periodic)
      throw std::logic_error("H5MD frame with a different number of spheres");
    if (precision == SnapshotPrecision::single) write_source(src, single_block);
    else write_source(src, double_block);
  }

  // A trajectory is written once and not read back by the run, so its pages need not stay
  // in the page cache: they are put on disk and dropped, and the next frames reuse the
  // same memory. A page the kernel has not used lately can cost far more to reclaim than
  // the copy into it (on virtual machines most of all), so a long trajectory written
  // plainly would spend its time in the kernel; synced (fdatasync) and dropped
  // (POSIX_FADV_DONTNEED) every kReleasePagesBytes, it reuses warm pages
  // (docs/performance.md, "Snapshots at N = 10^6"). A failed sync (a full disk) is an
  // error here, at the frame that caused it.
  void release_written_pages() {
    unreleased_bytes = 0;
    int* fd = nullptr;
    if (H5Fget_vfd_handle(file.get(), H5P_DEFAULT, reinterpret_cast<void**>(&fd)) < 0 || fd == nullptr) {
      H5Eclear2(H5E_DEFAULT);  // not the POSIX driver: nothing to release
      return;
    }
    if (::fdatasync(*fd) != 0) throw std::runtime_error(std::strerror(errno));
    ::posix_fadvise(*fd, 0, 0, POSIX_FADV_DONTNEED);  // advice only: its failure changes nothing written
  }

  void finish() {
    close_datasets();
    if (H5Fclose(file.release()) < 0) {
      H5Eclear2(H5E_DEFAULT);
      std::error_code ec;
      std::filesystem::remove(temporary, ec);
      throw OutputError(fmt::format("{}: cannot write: closing the HDF5 file failed (disk full?)", target.string()));
    }
    rename_into_place(temporary.string(), target.string());
    registered.release();
  }
};

template <int D>
H5mdWriter<D>::H5mdWriter(const std::string& path, const Particles<D>& particles, const std::string& config_toml,
                          SnapshotPrecision precision, bool pad_3d)
    : impl_(writing(path, [&] { return std::make_unique<Impl>(path, particles, config_toml, precision, pad_3d); })) {}

template <int D>
H5mdWriter<D>::H5mdWriter(const std::string& path, const Particles<D>& particles, std::uint64_t mark,
                          SnapshotPrecision precision, bool pad_3d)
    : impl_(std::make_unique<Impl>(path, particles, mark, precision, pad_3d)) {}

template <int D>
H5mdWriter<D>::~H5mdWriter() = default;

template <int D>
std::uint64_t H5mdWriter<D>::flush() {
  hdf5::quiet_errors();
  return writing(impl_->target, [&] { return impl_->flush(); });
}

// HDF5 (built thread-safe in Debian) keeps its error printing switch per thread, and
// frames are written on BackgroundWriter's thread: each call silences it on its own thread,
// so that a failure reaches the user as our one-line exception, not the library's trace.
template <int D>
void H5mdWriter<D>::write(const Frame<D>& frame) {
  hdf5::quiet_errors();
  writing(impl_->target, [&] { impl_->write(frame); });
}

template <int D>
void H5mdWriter<D>::write_source(const FrameSource<D>& source, const std::function<const Frame<D>&()>&) {
  hdf5::quiet_errors();
  writing(impl_->target, [&] { impl_->write(source); });
}

template <int D>
void H5mdWriter<D>::finish() {
  hdf5::quiet_errors();
  writing(impl_->target, [&] { impl_->finish(); });
}

template class H5mdWriter<2>;
template class H5mdWriter<3>;

}  // namespace ballagg
