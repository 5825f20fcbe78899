#pragma once
// One instant of a run as plain arrays: what trajectory files store and what `ballagg
// render` draws. The per-sphere constants (radius, mass) and the box live apart, in
// Particles, since they do not change during a run.
#include <cstdint>
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

// What a frame is computed from, copied out of the state in a few memcpy's: the run can
// go on while another thread turns it into a Frame (assemble_frame).
template <int D>
struct FrameSource {
  double time = 0.0;
  std::int64_t step = 0;
  int n_clusters = 0, largest_cluster = 0;
  double kinetic_energy = 0.0;
  Box<D> box;
  std::vector<Vec<D>> offset;             // per sphere, as in State::spheres
  std::vector<std::int32_t> cluster;
  std::vector<std::int32_t> slot;         // per cluster id: its index below (dead ids: unset)
  std::vector<Vec<D>> origin, velocity;   // per live cluster: body origin at `time`, velocity
  // Per live cluster when clusters rotate (State::spin; the body origin is then the centre
  // of mass): angular velocity. Empty otherwise.
  std::vector<Spin<D>> angular_velocity;
};

// The state at time t, for t from s.time up to the next event (positions are lazy). With
// `mirror_at_walls` (the time-stepping engine, whose walls act at the end of a step), a
// cluster that has flown through a wall since s.time is shown mirrored back, as the next
// step will put it (rule 2.2): frames between two steps show the free flight of step (i).
template <int D>
Frame<D> capture_frame(const State<D>& s, double t, std::int64_t step, bool mirror_at_walls = false);

// The two halves of capture_frame; both reuse the memory `out` already holds.
template <int D>
void capture_source(const State<D>& s, double t, std::int64_t step, bool mirror_at_walls, FrameSource<D>& out);
template <int D>
void assemble_frame(const FrameSource<D>& source, Frame<D>& out);

}  // namespace ballagg
