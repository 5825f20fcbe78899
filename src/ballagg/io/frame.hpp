#pragma once
// One instant of a run as plain arrays: what trajectory files store and what `ballagg
// render` draws. The per-sphere constants (radius, mass) and the box live apart, in
// Particles, since they do not change during a run.
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "ballagg/core/state.hpp"

namespace ballagg {

template <int D>
using Image = Eigen::Matrix<std::int32_t, D, 1>;

template <int D>
struct Frame {
  double time = 0.0;
  std::int64_t step = 0;             // events handled before this instant (ts: time steps)
  std::vector<Vec<D>> position;      // folded into a periodic box
  std::vector<Vec<D>> velocity;      // of the sphere: V + omega x (x - centre) for a rotating cluster
  // Periodic boxes: which copy of the box each sphere's unfolded position is in, so that
  // position + image * L puts every cluster in one piece (empty with walls).
  std::vector<Image<D>> image;
  std::vector<std::int32_t> cluster; // 0, 1, ... in order of each cluster's first sphere
  int n_clusters = 0;
  int largest_cluster = 0;           // spheres in the largest cluster
  double kinetic_energy = 0.0;

  int size() const { return static_cast<int>(position.size()); }
  // Position with the cluster in one piece across periodic faces.
  Vec<D> unwrapped(int i, double box_length) const {
    return image.empty() ? position[i] : Vec<D>(position[i] + box_length * image[i].template cast<double>());
  }
};

template <int D>
struct Particles {
  Box<D> box;
  std::vector<double> radius, mass;
  int size() const { return static_cast<int>(radius.size()); }
};

template <int D>
Particles<D> particles_of(const State<D>& s);

// The sphere layout of a frame (State::spheres' offsets and cluster ids), at one
// State::layout_version. Frames between which the layout did not change share one copy:
// in an aggregating run merges grow rare as the clusters do, so most frames come after the
// last merge before them, and with few clusters left the copy of the layout is most of
// what a frame costs the run.
template <int D>
struct SphereLayout {
  std::uint64_t version = 0;
  std::vector<Vec<D>> offset;
  std::vector<std::int32_t> cluster;
};

// Hands out copies of a state's layout: the last one again while the state's
// layout_version is the same, else a new copy made in the memory of a copy that no frame
// holds any more (no allocation, no page faults once a run has started). Frames may let
// go of their copies on any thread (a frame writer's). Not thread-safe otherwise: one
// caller (the run's thread).
template <int D>
class LayoutCopies {
 public:
  LayoutCopies();
  std::shared_ptr<const SphereLayout<D>> of(const State<D>& s);

 private:
  struct Spares;  // copies no frame holds, behind a mutex
  std::shared_ptr<Spares> spares_;
  std::shared_ptr<const SphereLayout<D>> last_;
};

// What a frame is computed from, copied out of the state in a few memcpy's (the layout
// only when it changed): the run can go on while another thread turns it into a Frame
// (assemble_frame).
template <int D>
struct FrameSource {
  double time = 0.0;
  std::int64_t step = 0;
  int n_clusters = 0, largest_cluster = 0;
  double kinetic_energy = 0.0;
  Box<D> box;
  std::shared_ptr<const SphereLayout<D>> layout;  // per sphere: offset and cluster id
  std::vector<std::int32_t> slot;         // per cluster id: its index below (dead ids: unset)
  std::vector<Vec<D>> origin, velocity;   // per live cluster: body origin at `time`, velocity
  // Per live cluster when clusters rotate (State::spin; the body origin is then the centre
  // of mass): angular velocity. Empty otherwise.
  std::vector<Spin<D>> angular_velocity;

  int size() const { return layout ? static_cast<int>(layout->cluster.size()) : 0; }
  // The memory the source holds, its layout included (what BackgroundWriter's budget
  // counts; a layout shared by several sources is counted in each).
  std::size_t bytes() const;
};

// The state at time t, for t from s.time up to the next event (positions are lazy). With
// `mirror_at_walls` (the time-stepping engine, whose walls act at the end of a step), a
// cluster that has flown through a wall since s.time is shown mirrored back, as the next
// step will put it (rule 2.2): frames between two steps show the free flight of step (i).
template <int D>
Frame<D> capture_frame(const State<D>& s, double t, std::int64_t step, bool mirror_at_walls = false);

// The two halves of capture_frame; both reuse the memory `out` already holds. The layout
// comes from `layouts` (shared with the previous frame's when unchanged).
template <int D>
void capture_source(const State<D>& s, double t, std::int64_t step, bool mirror_at_walls, FrameSource<D>& out,
                    LayoutCopies<D>& layouts);
template <int D>
void assemble_frame(const FrameSource<D>& source, Frame<D>& out);

// assemble_frame piece by piece: spheres [begin, end) at a time, in order, into flat arrays
// (D values per sphere) of any floating-point type. A writer can so assemble and write a
// frame one block at a time while the block is in cache, and store single precision without
// a frame of doubles in between. Positions and velocities are computed in double, as
// assemble_frame does, and rounded once.
template <int D>
class FrameAssembler {
 public:
  // Starts the frame of `source` (which must outlive the calls to assemble).
  void start(const FrameSource<D>& source);
  // Spheres [begin, end), where begin is where the previous call ended (0 after start).
  // `image` is written only for a periodic box (it may be null otherwise).
  template <class Real>
  void assemble(int begin, int end, Real* position, Real* velocity, std::int32_t* image, std::int32_t* cluster);

 private:
  const FrameSource<D>* source_ = nullptr;
  std::vector<std::int32_t> label_;  // per live cluster: its id in the frame, -1 before its first sphere
  std::int32_t next_label_ = 0;
  int assembled_ = 0;                // spheres done
};

}  // namespace ballagg
