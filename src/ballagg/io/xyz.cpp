#include "ballagg/io/xyz.hpp"

#include <vector>

#include <fmt/format.h>

namespace ballagg {

template <int D>
std::string xyz_frame_text(const State<D>& s) {
  const double l = s.box.length;
  // A 2D box gets a third cell vector one diameter deep, so viewers see a flat slab.
  const double lz = D == 3 ? l : 2.0 * s.max_radius();
  const char* p = s.box.periodic() ? "T" : "F";
  fmt::memory_buffer out;
  auto to = std::back_inserter(out);
  fmt::format_to(to, "{}\n", s.n_spheres());
  fmt::format_to(to,
                 "Lattice=\"{} 0 0 0 {} 0 0 0 {}\" Origin=\"0 0 0\" "
                 "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:cluster:I:1 pbc=\"{} {} {}\" Time={}\n",
                 l, l, lz, p, p, D == 3 ? p : "F", s.time);
  std::vector<int> label(s.clusters.size(), -1);
  int next = 0;
  for (int i = 0; i < s.n_spheres(); ++i) {
    const Vec<D> x = s.position(i, s.time);
    const Vec<D>& v = s.velocity(i);
    int& id = label[s.spheres.cluster[i]];
    if (id < 0) id = next++;
    if constexpr (D == 2)
      fmt::format_to(to, "S {} {} 0 {} {} 0 {} {}\n", x[0], x[1], v[0], v[1], s.spheres.radius[i], id);
    else
      fmt::format_to(to, "S {} {} {} {} {} {} {} {}\n", x[0], x[1], x[2], v[0], v[1], v[2], s.spheres.radius[i], id);
  }
  return fmt::to_string(out);
}

template std::string xyz_frame_text<2>(const State<2>&);
template std::string xyz_frame_text<3>(const State<3>&);

}  // namespace ballagg
