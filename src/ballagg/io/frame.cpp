#include "ballagg/io/frame.hpp"

#include "ballagg/engines/time_stepping/walls.hpp"

namespace ballagg {

template <int D>
Particles<D> particles_of(const State<D>& s) {
  return {s.box, s.spheres.radius, s.spheres.mass};
}

template <int D>
Frame<D> capture_frame(const State<D>& s, double t, std::int64_t step, bool mirror_at_walls) {
  const int n = s.n_spheres();
  Frame<D> f;
  f.time = t;
  f.step = step;
  f.n_clusters = s.n_clusters();
  f.largest_cluster = s.largest_cluster();
  f.kinetic_energy = s.running_kinetic_energy();
  // Per cluster: body origin at t and velocity; labels in order of first sphere.
  std::vector<Vec<D>> origin(s.clusters.size()), velocity(s.clusters.size());
  for (int c : s.alive_clusters()) {
    origin[c] = s.origin(c, t);
    velocity[c] = s.clusters[c].velocity;
    if (mirror_at_walls && !s.box.periodic()) {
      const WallCorrection<D> w = wall_correction(s, c, t);
      origin[c] += w.shift;
      velocity[c] = w.velocity;
    }
  }
  std::vector<std::int32_t> label(s.clusters.size(), -1);
  f.position.resize(n);
  f.velocity.resize(n);
  f.cluster.resize(n);
  if (s.box.periodic()) f.image.resize(n);
  std::int32_t next = 0;
  const double length = s.box.length;
  for (int i = 0; i < n; ++i) {
    const int c = s.spheres.cluster[i];
    // The same sum as State::position, so the last frame equals final.csv bit for bit.
    const Vec<D> x = origin[c] + s.spheres.offset[i];
    f.position[i] = s.box.wrap(x);
    f.velocity[i] = velocity[c];
    if (s.box.periodic())
      for (int a = 0; a < D; ++a) f.image[i][a] = static_cast<std::int32_t>(std::lround((x[a] - f.position[i][a]) / length));
    std::int32_t& l = label[c];
    if (l < 0) l = next++;
    f.cluster[i] = l;
  }
  return f;
}

template Particles<2> particles_of<2>(const State<2>&);
template Particles<3> particles_of<3>(const State<3>&);
template Frame<2> capture_frame<2>(const State<2>&, double, std::int64_t, bool);
template Frame<3> capture_frame<3>(const State<3>&, double, std::int64_t, bool);

}  // namespace ballagg
