#include "ballagg/render/pov_scene.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace ballagg {

namespace {

// Our right-handed z-up coordinates in POV-Ray's left-handed y-up frame.
std::string pov_vector(const Vec<3>& v) { return fmt::format("<{}, {}, {}>", v[0], v[2], v[1]); }

}  // namespace

std::string pov_scene_text(const Scene<3>& s, const View3& view) {
  // Centre on the middle of the aggregate as the camera sees it, and step back until its
  // whole outline fits in the view angle (the nearest spheres look largest).
  const CameraFrame cam(view.towards_viewer);
  double lo_u = 1e300, hi_u = -1e300, lo_v = 1e300, hi_v = -1e300, lo_w = 1e300, hi_w = -1e300;
  for (int i = 0; i < s.size(); ++i) {
    const Vec<3>& c = s.centre[i];
    const double r = s.radius[i];
    lo_u = std::min(lo_u, c.dot(cam.right) - r), hi_u = std::max(hi_u, c.dot(cam.right) + r);
    lo_v = std::min(lo_v, c.dot(cam.up) - r), hi_v = std::max(hi_v, c.dot(cam.up) + r);
    lo_w = std::min(lo_w, c.dot(cam.back) - r), hi_w = std::max(hi_w, c.dot(cam.back) + r);
  }
  const Vec<3> centre = 0.5 * ((lo_u + hi_u) * cam.right + (lo_v + hi_v) * cam.up + (lo_w + hi_w) * cam.back);
  constexpr double kAngleDegrees = 30.0;
  const double half_span = 0.5 * std::max(hi_u - lo_u, hi_v - lo_v);
  const double distance = 0.5 * (hi_w - lo_w) + 1.08 * half_span / std::tan(0.5 * kAngleDegrees * std::numbers::pi / 180.0);
  const Vec<3> eye = centre + distance * cam.back;
  // The light comes from the picture's frame direction, far away.
  const Vec<3> light_dir = (view.light[0] * cam.right + view.light[1] * cam.up + view.light[2] * cam.back).normalized();
  const Vec<3> key = centre + 3.0 * distance * light_dir;
  const Vec<3> fill = centre + 3.0 * distance * (cam.back - 0.5 * light_dir).normalized();
  std::string out;
  auto to = std::back_inserter(out);
  fmt::format_to(to, "// ballagg: {} spheres at t = {}{}\n", s.size(), s.time,
                 s.whole_box ? "" : fmt::format(", aggregate {} by size", s.aggregate_rank));
  fmt::format_to(to, "// Render: povray +W1200 +H1200 +A0.3 +O<picture>.png <this file>\n");
  fmt::format_to(to, "#version 3.7;\nglobal_settings {{ assumed_gamma 1.0 }}\n");
  fmt::format_to(to, "background {{ color rgb <1, 1, 1> }}\n");
  fmt::format_to(to, "camera {{\n  perspective\n  location {}\n  look_at {}\n  sky {}\n  right x\n  up y\n  angle {}\n}}\n",
                 pov_vector(eye), pov_vector(centre), pov_vector(cam.up), kAngleDegrees);
  const double soft = 0.05 * distance;
  fmt::format_to(to,
                 "light_source {{ {} color rgb <1, 1, 1>\n  area_light {}, {}, 4, 4 adaptive 1 jitter circular orient }}\n",
                 pov_vector(key), pov_vector(soft * cam.right), pov_vector(soft * cam.up));
  fmt::format_to(to, "light_source {{ {} color rgb <0.35, 0.35, 0.4> shadowless }}\n", pov_vector(fill));
  fmt::format_to(to, "#declare Shine = finish {{ ambient 0.06 diffuse 0.8 specular 0.5 roughness 0.012 }}\n");
  for (int k = 0; k < static_cast<int>(kClusterColours.size()); ++k) {
    const Rgb& c = kClusterColours[k];
    fmt::format_to(to, "#declare Colour{} = texture {{ pigment {{ color srgb <{}, {}, {}> }} finish {{ Shine }} }}\n", k,
                   c.r, c.g, c.b);
  }
  fmt::format_to(to, "union {{\n");
  for (int i = 0; i < s.size(); ++i)
    fmt::format_to(to, "  sphere {{ {}, {} texture {{ Colour{} }} }}\n", pov_vector(s.centre[i]), s.radius[i],
                   static_cast<int>(s.colour[i]));
  fmt::format_to(to, "}}\n");
  return out;
}

}  // namespace ballagg
