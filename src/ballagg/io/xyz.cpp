#include "ballagg/io/xyz.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ballagg/io/chunked_text.hpp"

namespace ballagg {

template <int D>
void write_xyz_frame(const Frame<D>& f, const Particles<D>& p, ByteSink& sink) {
  const double l = p.box.length;
  // A 2D box gets a third cell vector one diameter deep, so viewers see a flat slab.
  const double lz = D == 3 ? l : 2.0 * *std::max_element(p.radius.begin(), p.radius.end());
  const char* pbc = p.box.periodic() ? "T" : "F";
  ChunkedText out(sink);
  auto to = out.out();
  fmt::format_to(to, "{}\n", f.size());
  fmt::format_to(to,
                 "Lattice=\"{} 0 0 0 {} 0 0 0 {}\" Origin=\"0 0 0\" "
                 "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:cluster:I:1 pbc=\"{} {} {}\" Time={}\n",
                 l, l, lz, pbc, pbc, D == 3 ? pbc : "F", f.time);
  for (int i = 0; i < f.size(); ++i) {
    const Vec<D>& x = f.position[i];
    const Vec<D>& v = f.velocity[i];
    if constexpr (D == 2)
      fmt::format_to(to, "S {} {} 0 {} {} 0 {} {}\n", x[0], x[1], v[0], v[1], p.radius[i], f.cluster[i]);
    else
      fmt::format_to(to, "S {} {} {} {} {} {} {} {}\n", x[0], x[1], x[2], v[0], v[1], v[2], p.radius[i], f.cluster[i]);
    out.end_line();
  }
  out.flush();
}

template <int D>
void append_xyz_frame(std::string& text, const Frame<D>& f, const Particles<D>& p) {
  StringSink sink(text);
  write_xyz_frame(f, p, sink);
}

template <int D>
std::string xyz_frame_text(const State<D>& s) {
  std::string text;
  append_xyz_frame(text, capture_frame(s, s.time, 0), particles_of(s));
  return text;
}

template <int D>
void write_xyz_frame(const State<D>& s, ByteSink& out) {
  write_xyz_frame(capture_frame(s, s.time, 0), particles_of(s), out);
}

template void append_xyz_frame<2>(std::string&, const Frame<2>&, const Particles<2>&);
template void append_xyz_frame<3>(std::string&, const Frame<3>&, const Particles<3>&);
template std::string xyz_frame_text<2>(const State<2>&);
template std::string xyz_frame_text<3>(const State<3>&);
template void write_xyz_frame<2>(const Frame<2>&, const Particles<2>&, ByteSink&);
template void write_xyz_frame<3>(const Frame<3>&, const Particles<3>&, ByteSink&);
template void write_xyz_frame<2>(const State<2>&, ByteSink&);
template void write_xyz_frame<3>(const State<3>&, ByteSink&);

}  // namespace ballagg
