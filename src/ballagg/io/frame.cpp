#include "ballagg/io/frame.hpp"

#include <cmath>

#include "ballagg/engines/time_stepping/walls.hpp"

namespace ballagg {

template <int D>
Particles<D> particles_of(const State<D>& s) {
  return {s.box, s.spheres.radius, s.spheres.mass};
}

template <int D>
void capture_source(const State<D>& s, double t, std::int64_t step, bool mirror_at_walls, FrameSource<D>& out) {
  out.time = t;
  out.step = step;
  out.n_clusters = s.n_clusters();
  out.largest_cluster = s.largest_cluster();
  out.kinetic_energy = s.running_kinetic_energy();
  out.box = s.box;
  out.offset = s.spheres.offset;  // reuses out's memory: a memcpy
  out.cluster = s.spheres.cluster;
  // Only live clusters are read and stored: late in a run they are few.
  if (out.slot.size() != s.clusters.size()) out.slot.resize(s.clusters.size());
  out.origin.resize(s.alive_clusters().size());
  out.velocity.resize(s.alive_clusters().size());
  out.angular_velocity.resize(s.spin.empty() ? 0 : s.alive_clusters().size());
  std::int32_t k = 0;
  for (int c : s.alive_clusters()) {
    out.slot[c] = k;
    out.origin[k] = s.origin(c, t);
    out.velocity[k] = s.clusters[c].velocity;
    if (!s.spin.empty()) out.angular_velocity[k] = s.spin[c].angular_velocity;
    if (mirror_at_walls && !s.box.periodic()) {
      const WallCorrection<D> w = wall_correction(s, c, t);
      out.origin[k] += w.shift;
      out.velocity[k] = w.velocity;
    }
    ++k;
  }
}

template <int D>
void assemble_frame(const FrameSource<D>& src, Frame<D>& f) {
  const int n = static_cast<int>(src.cluster.size());
  f.time = src.time;
  f.step = src.step;
  f.n_clusters = src.n_clusters;
  f.largest_cluster = src.largest_cluster;
  f.kinetic_energy = src.kinetic_energy;
  f.position.resize(n);
  f.velocity.resize(n);
  f.cluster.resize(n);
  f.image.resize(src.box.periodic() ? n : 0);
  // Labels in order of each cluster's first sphere.
  std::vector<std::int32_t> label(src.origin.size(), -1);
  std::int32_t next = 0;
  const double length = src.box.length;
  for (int i = 0; i < n; ++i) {
    const int c = src.slot[src.cluster[i]];
    // The same sum as State::position, so the last frame equals final.csv bit for bit.
    const Vec<D> x = src.origin[c] + src.offset[i];
    f.position[i] = src.box.wrap(x);
    f.velocity[i] = src.velocity[c];
    if (!src.angular_velocity.empty()) f.velocity[i] += cross(src.angular_velocity[c], src.offset[i]);
    if (src.box.periodic())
      for (int a = 0; a < D; ++a)
        f.image[i][a] = static_cast<std::int32_t>(std::lround((x[a] - f.position[i][a]) / length));
    std::int32_t& l = label[c];
    if (l < 0) l = next++;
    f.cluster[i] = l;
  }
}

template <int D>
Frame<D> capture_frame(const State<D>& s, double t, std::int64_t step, bool mirror_at_walls) {
  FrameSource<D> source;
  capture_source(s, t, step, mirror_at_walls, source);
  Frame<D> f;
  assemble_frame(source, f);
  return f;
}

template Particles<2> particles_of<2>(const State<2>&);
template Particles<3> particles_of<3>(const State<3>&);
template void capture_source<2>(const State<2>&, double, std::int64_t, bool, FrameSource<2>&);
template void capture_source<3>(const State<3>&, double, std::int64_t, bool, FrameSource<3>&);
template void assemble_frame<2>(const FrameSource<2>&, Frame<2>&);
template void assemble_frame<3>(const FrameSource<3>&, Frame<3>&);
template Frame<2> capture_frame<2>(const State<2>&, double, std::int64_t, bool);
template Frame<3> capture_frame<3>(const State<3>&, double, std::int64_t, bool);

}  // namespace ballagg
