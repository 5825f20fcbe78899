#include "ballagg/io/h5md_reader.hpp"

#include <filesystem>

#include <fmt/format.h>

#include "ballagg/core/input_error.hpp"
#include "ballagg/io/hdf5_handle.hpp"

namespace ballagg {

using hdf5::Handle;

template <int D>
struct H5mdReader<D>::Impl {
  std::string path;
  Handle file;
  Particles<D> particles;
  int frames = 0;
  int stored = D;  // dimensions per sphere in the file: D, or 3 for a 2D run padded to 3D
  Handle time, step, position, velocity, image, cluster, clusters, largest, energy;

  explicit Impl(const std::string& p) : path(p) {
    hdf5::quiet_errors();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw InputError(fmt::format("{}: no such file (run with output.snapshot_every > 0 to write a trajectory)", path));
    file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (file.get() < 0) throw InputError(fmt::format("{}: cannot read: not an HDF5 file", path));
    try {
      read();
    } catch (const std::runtime_error& e) {
      if (dynamic_cast<const InputError*>(&e)) throw;
      throw InputError(fmt::format("{}: not a ballagg H5MD trajectory ({})", path, e.what()));
    }
  }

  void read() {
    const Handle all = hdf5::open_group(file, "particles/all");
    const Handle box = hdf5::open_group(all, "box");
    const std::vector<std::int32_t> dimension = hdf5::read_int_attribute(box, "dimension");
    stored = dimension.size() == 1 ? dimension[0] : 0;
    // A 2D run stored in 3D says so; a file that does not holds a run of its box's dimension.
    const int padded_from = run_dimension();
    const int run = padded_from != 0 ? padded_from : stored;
    if (run != D || (stored != D && !(D == 2 && stored == 3)))
      throw InputError(fmt::format("{}: a {}D trajectory, but config.toml says {}D", path, run, D));
    particles.box.length = box_length(box);
    particles.radius = hdf5::read_doubles(all, "radius");
    particles.mass = hdf5::read_doubles(all, "mass");
    particles.box.boundary = hdf5::exists(all, "image") ? Boundary::periodic : Boundary::walls;
    time = hdf5::open_dataset(all, "position/time");
    step = hdf5::open_dataset(all, "position/step");
    position = hdf5::open_dataset(all, "position/value");
    velocity = hdf5::open_dataset(all, "velocity/value");
    cluster = hdf5::open_dataset(all, "cluster/value");
    if (particles.box.periodic()) image = hdf5::open_dataset(all, "image/value");
    clusters = hdf5::open_dataset(file, "observables/clusters/value");
    largest = hdf5::open_dataset(file, "observables/largest_cluster/value");
    energy = hdf5::open_dataset(file, "observables/kinetic_energy/value");
    const std::vector<hsize_t> dims = hdf5::dimensions(position);
    if (dims.size() != 3 || dims[1] != particles.radius.size() || dims[2] != static_cast<hsize_t>(stored))
      throw std::runtime_error("position/value has the wrong shape");
    frames = static_cast<int>(dims[0]);
  }

  // The dimension of the run a file padded to 3D comes from (parameters' attribute), or 0.
  int run_dimension() const {
    const Handle parameters = hdf5::open_group(file, "parameters");
    if (H5Aexists(parameters, "dimension") <= 0) return 0;
    const std::vector<std::int32_t> d = hdf5::read_int_attribute(parameters, "dimension");
    return d.size() == 1 ? d[0] : 0;
  }

  // The box length: edges is a vector (time-independent) or, in the 3D layout, a series of
  // edge matrices (the box does not change: the first is read).
  double box_length(hid_t box) const {
    if (!hdf5::exists(box, "edges/value")) {
      const std::vector<double> edges = hdf5::read_doubles(box, "edges");
      if (edges.size() != static_cast<std::size_t>(D)) throw std::runtime_error("box/edges");
      return edges[0];
    }
    const Handle edges = hdf5::open_dataset(box, "edges/value");
    const std::vector<hsize_t> dims = hdf5::dimensions(edges);
    const hsize_t s = static_cast<hsize_t>(stored);
    if (dims.size() != 3 || dims[0] < 1 || dims[1] != s || dims[2] != s) throw std::runtime_error("box/edges/value");
    std::vector<double> matrix;
    hdf5::read_record(edges, 0, matrix);
    return matrix.at(0);
  }
};

template <int D>
H5mdReader<D>::H5mdReader(const std::string& path) : impl_(std::make_unique<Impl>(path)) {}
template <int D>
H5mdReader<D>::~H5mdReader() = default;
template <int D>
H5mdReader<D>::H5mdReader(H5mdReader&&) noexcept = default;

template <int D>
int H5mdReader<D>::frames() const {
  return impl_->frames;
}

template <int D>
const Particles<D>& H5mdReader<D>::particles() const {
  return impl_->particles;
}

template <int D>
Frame<D> H5mdReader<D>::frame(int k) const {
  const Impl& m = *impl_;
  if (k < 0 || k >= m.frames)
    throw InputError(fmt::format("--frame {}: {} has {} frames (0 to {})", k, m.path, m.frames, m.frames - 1));
  Frame<D> f;
  try {
    const hsize_t r = static_cast<hsize_t>(k);
    std::vector<double> doubles;
    std::vector<std::int32_t> ints;
    std::vector<std::int64_t> longs;
    hdf5::read_record(m.time, r, doubles);
    f.time = doubles.at(0);
    hdf5::read_record(m.step, r, longs);
    f.step = longs.at(0);
    hdf5::read_record(m.energy, r, doubles);
    f.kinetic_energy = doubles.at(0);
    hdf5::read_record(m.clusters, r, ints);
    f.n_clusters = ints.at(0);
    hdf5::read_record(m.largest, r, ints);
    f.largest_cluster = ints.at(0);
    const int n = m.particles.size();
    auto vectors = [&](hid_t dataset, std::vector<Vec<D>>& out) {
      hdf5::read_record(dataset, r, doubles);
      out.resize(n);
      for (int i = 0; i < n; ++i)
        for (int a = 0; a < D; ++a) out[i][a] = doubles[static_cast<std::size_t>(i) * m.stored + a];
    };
    vectors(m.position, f.position);
    vectors(m.velocity, f.velocity);
    hdf5::read_record(m.cluster, r, f.cluster);
    if (m.particles.box.periodic()) {
      hdf5::read_record(m.image, r, ints);
      f.image.resize(n);
      for (int i = 0; i < n; ++i)
        for (int a = 0; a < D; ++a) f.image[i][a] = ints[static_cast<std::size_t>(i) * m.stored + a];
    }
  } catch (const std::runtime_error& e) {
    throw InputError(fmt::format("{}: cannot read frame {} ({})", m.path, k, e.what()));
  }
  return f;
}

template <int D>
std::vector<double> H5mdReader<D>::times() const {
  std::vector<double> t;
  try {
    t = hdf5::read_doubles(impl_->file, "particles/all/position/time");
  } catch (const std::runtime_error& e) {
    throw InputError(fmt::format("{}: cannot read the frame times ({})", impl_->path, e.what()));
  }
  if (t.size() < static_cast<std::size_t>(impl_->frames))
    throw InputError(fmt::format("{}: {} frame times for {} frames", impl_->path, t.size(), impl_->frames));
  t.resize(static_cast<std::size_t>(impl_->frames));
  return t;
}

template class H5mdReader<2>;
template class H5mdReader<3>;

}  // namespace ballagg
