#pragma once
// trajectory.gsd: frames in HOOMD-blue's GSD format (file layer 2.0, schema "hoomd" 1.4;
// https://gsd.readthedocs.io), read by HOOMD-blue, OVITO and the gsd Python package. Debian
// ships no GSD C library, so this writes the file layer itself: a 256-byte header, the
// frames' data chunks one after the other, and at finish() the name list and the index
// (entries sorted by frame, then by name id), which the header then points to.
//
// Chunks (N spheres; HOOMD takes a chunk missing from a frame from frame 0):
//   frame 0 only     configuration/dimensions (uint8: D), configuration/box (float32
//                    [Lx, Ly, Lz, 0, 0, 0]; 2D: Lz = 0), particles/N, particles/types ("S"),
//                    particles/typeid (0), particles/mass, particles/diameter (2 radius)
//   every frame      configuration/step (uint64: events or time steps), particles/position
//                    (float32 [N][3]), particles/velocity (float32 [N][3]), particles/body
//                    (int32: the cluster id), particles/image (int32 [N][3], periodic boxes),
//                    log/time, log/kinetic_energy (float64), log/clusters,
//                    log/largest_cluster (int32)
// HOOMD's box is centred on the origin: positions are ballagg's minus L/2 in every axis
// (2D: z = 0), computed in double and rounded to float32 once, as HOOMD's schema stores
// them. particles/body is HOOMD's rigid-body id; ballagg's cluster ids are 0, 1, ... in
// order of each cluster's first sphere, a lone sphere being a cluster of its own (never
// HOOMD's -1 for a free particle). The simulated time has no place in HOOMD's schema
// (HOOMD's time is step * dt): it is the logged quantity log/time.
#include <cstdint>
#include <string>
#include <vector>

#include "ballagg/io/atomic_file.hpp"
#include "ballagg/io/frame_sink.hpp"

namespace ballagg {

template <int D>
class GsdWriter final : public FrameSink<D> {
 public:
  // Writes to a temporary file next to `path`, renamed to `path` by finish(). Every
  // failure to write throws OutputError naming `path`.
  GsdWriter(const std::string& path, const Particles<D>& particles);
  // A resumed run: continues the temporary file left by a checkpointed one, cut back to
  // `mark` frames (what flush() returned). Throws InputError if it is missing or shorter.
  GsdWriter(const std::string& path, const Particles<D>& particles, std::uint64_t mark);
  void write(const Frame<D>& frame) override;
  void finish() override;
  std::uint64_t flush() override;  // the mark: frames written

  // One entry of the file's index (the layout of struct gsd_index_entry, 32 bytes).
  struct IndexEntry {
    std::uint64_t frame = 0, n = 0;
    std::int64_t location = 0;
    std::uint32_t m = 0;
    std::uint16_t id = 0;
    std::uint8_t type = 0, flags = 0;
  };

 private:
  // The chunks of frame `frame`, in name-id order, and their place in the file from
  // bytes_ on (bytes_ advances past them).
  void index_frame(std::uint64_t frame);
  void append_frame_data(const Frame<D>& frame);

  Particles<D> particles_;
  AtomicFile file_;  // removes the temporary file unless finished or a checkpoint refers to it
  std::vector<IndexEntry> index_;
  std::uint64_t frames_ = 0;
  std::uint64_t bytes_ = 0;  // file size so far
  std::string data_;         // one frame's chunks, reused
};

}  // namespace ballagg
