#pragma once
// Trajectory frames in an H5MD 1.1 file (HDF5, https://nongnu.org/h5md; read with h5py,
// MDAnalysis, or any H5MD reader). Layout (N spheres, F frames; group "all"; S stored
// dimensions: D, or 3 for a 2D run with output.h5md_pad_3d):
//
//   h5md/                 version = {1, 1}; author/ (name), creator/ (name, version)
//   particles/all/
//     box/                dimension = S, boundary = "periodic" | "none" (x S; a padded z: "none")
//       edges             S = 2: double[2] (time-independent);
//                         S = 3: step, time, value: double[F][3][3] (rows: edge vectors)
//     position/           step: int64[F], time: double[F], value: real[F][N][S] (folded)
//     image/              periodic only: value int32[F][N][S]; unwrapped = position + image * edges
//     velocity/           value: real[F][N][S]
//     cluster/            value: int32[F][N], 0, 1, ... in order of each cluster's first sphere
//     radius, mass        double[N] (time-independent)
//   observables/          clusters, largest_cluster (int32[F]), kinetic_energy (double[F])
//   parameters/           config.toml (the resolved configuration), ballagg_version;
//                         attribute dimension = 2 when a 2D run is stored in 3D
//
// S = 3 is the layout 3D readers need (MDAnalysis reads no other): the box per frame, as a
// matrix, and `unit` attributes on position/value, position/time, velocity/value and
// box/edges/value (kLengthUnit and friends in the .cpp say which and why). A padded 2D run
// stores z = 0 (positions, velocities, images) and a box one largest diameter deep in z.
//
// real is float32 or float64 (output.snapshot_precision): the positions and velocities,
// computed in double, rounded to nearest once. Every time-dependent group shares position's
// step and time datasets (hard links). Per-sphere values are chunked by frame and by blocks
// of at most 65536 spheres, and written block by block, each block assembled right before
// (FrameAssembler): a frame never exists whole in memory. Images are compressed (shuffle +
// deflate level 1: nearly all zeros); positions, velocities and cluster ids are not
// (floats barely compress, and deflating the ids would cost the writer thread more time
// than it saves on the disk). No timestamps are written, so the same run gives a
// byte-identical file.
#include <memory>
#include <string>

#include "ballagg/config/config.hpp"
#include "ballagg/io/frame_sink.hpp"

namespace ballagg {

template <int D>
class H5mdWriter final : public FrameSink<D> {
 public:
  // Creates a temporary file next to `path`, renamed to `path` by finish(). Throws
  // std::runtime_error if it cannot be created.
  // `pad_3d`: a 2D run stored in 3D (output.h5md_pad_3d; no effect in 3D).
  H5mdWriter(const std::string& path, const Particles<D>& particles, const std::string& config_toml,
             SnapshotPrecision precision = SnapshotPrecision::single, bool pad_3d = false);
  // A resumed run: reopens the temporary file left by a checkpointed one, cut back to
  // `mark` frames (what flush() returned). Throws InputError if it is missing or damaged.
  H5mdWriter(const std::string& path, const Particles<D>& particles, std::uint64_t mark,
             SnapshotPrecision precision = SnapshotPrecision::single, bool pad_3d = false);
  ~H5mdWriter() override;
  void write(const Frame<D>& frame) override;
  // The same file as write(assembled()), without the frame of doubles in between.
  void write_source(const FrameSource<D>& source, const std::function<const Frame<D>&()>& assembled) override;
  void finish() override;
  // H5Fflush: the file on disk holds every frame so far. The mark: frames written.
  std::uint64_t flush() override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ballagg
