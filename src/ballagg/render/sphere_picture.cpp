#include "ballagg/render/sphere_picture.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

namespace ballagg {

CameraFrame::CameraFrame(const Vec<3>& towards_viewer) {
  back = towards_viewer.normalized();
  Vec<3> world_up(0.0, 0.0, 1.0);
  if (std::abs(back.dot(world_up)) > 0.999) world_up = Vec<3>(0.0, 1.0, 0.0);
  right = world_up.cross(back).normalized();
  up = back.cross(right);
}

namespace {

constexpr float kEmpty = -std::numeric_limits<float>::infinity();

// The supersampled panel: depth (along `back`, larger is nearer) and colour per sample.
class Raster {
 public:
  Raster(int size, const CameraFrame& cam, const Vec<3>& origin, double scale)
      : size_(size), cam_(cam), origin_(origin), scale_(scale),
        depth_(static_cast<std::size_t>(size) * size, kEmpty),
        rgb_(static_cast<std::size_t>(size) * size, {1.0f, 1.0f, 1.0f}) {}

  // Screen coordinates of a world point: pixel x, pixel y (down), depth.
  Vec<3> project(const Vec<3>& p) const {
    const Vec<3> d = p - origin_;
    return {d.dot(cam_.right) * scale_, -d.dot(cam_.up) * scale_, d.dot(cam_.back)};
  }
  // The world point on the screen plane (depth 0) under the centre of sample (x, y).
  Vec<3> world_at(int x, int y) const {
    return origin_ + ((x + 0.5) / scale_) * cam_.right - ((y + 0.5) / scale_) * cam_.up;
  }

  // One sphere. With `box_length` > 0 the sphere is cut by the faces of [0, L]^3.
  void sphere(const Vec<3>& centre, double radius, const Rgb& colour, const Vec<3>& light, const SphereShading& sh,
              double box_length) {
    const Vec<3> c = project(centre);
    const double r = radius * scale_;
    const int x0 = std::max(0, static_cast<int>(std::floor(c[0] - r))),
              x1 = std::min(size_ - 1, static_cast<int>(std::ceil(c[0] + r)));
    const int y0 = std::max(0, static_cast<int>(std::floor(c[1] - r))),
              y1 = std::min(size_ - 1, static_cast<int>(std::ceil(c[1] + r)));
    const Vec<3> half = (light + Vec<3>(0.0, 0.0, 1.0)).normalized();
    for (int y = y0; y <= y1; ++y) {
      const double dy = (y + 0.5) - c[1];
      for (int x = x0; x <= x1; ++x) {
        const double dx = (x + 0.5) - c[0];
        const double d2 = dx * dx + dy * dy;
        if (d2 >= r * r) continue;
        const double dz = std::sqrt(r * r - d2);
        double front = c[2] + dz / scale_;
        Vec<3> normal(dx / r, -dy / r, dz / r);  // camera frame
        if (box_length > 0.0 && !cut_by_box(x, y, front, c[2] - dz / scale_, box_length, normal)) continue;
        const std::size_t k = static_cast<std::size_t>(y) * size_ + x;
        if (front <= depth_[k]) continue;
        depth_[k] = static_cast<float>(front);
        const double diffuse = std::max(0.0, normal.dot(light));
        const double highlight = std::pow(std::max(0.0, normal.dot(half)), sh.shininess);
        const double lit = sh.ambient + sh.diffuse * diffuse, spec = sh.specular * highlight;
        rgb_[k] = {static_cast<float>(std::min(1.0, colour.r * lit + spec)),
                   static_cast<float>(std::min(1.0, colour.g * lit + spec)),
                   static_cast<float>(std::min(1.0, colour.b * lit + spec))};
      }
    }
  }

  // A line segment between world points, `width` samples wide, hidden behind anything
  // nearer than `bias` in front of it.
  void segment(const Vec<3>& a, const Vec<3>& b, double width, const std::array<float, 3>& colour, double bias) {
    const Vec<3> pa = project(a), pb = project(b);
    const double length = std::hypot(pb[0] - pa[0], pb[1] - pa[1]);
    const int steps = std::max(1, static_cast<int>(std::ceil(2.0 * length)));
    const int half = std::max(0, static_cast<int>(std::floor(0.5 * width)));
    for (int s = 0; s <= steps; ++s) {
      const Vec<3> p = pa + (pb - pa) * (static_cast<double>(s) / steps);
      const int cx = static_cast<int>(std::floor(p[0])), cy = static_cast<int>(std::floor(p[1]));
      for (int y = cy - half; y <= cy + half; ++y) {
        for (int x = cx - half; x <= cx + half; ++x) {
          if (x < 0 || y < 0 || x >= size_ || y >= size_) continue;
          const std::size_t k = static_cast<std::size_t>(y) * size_ + x;
          if (depth_[k] > p[2] + bias) continue;
          rgb_[k] = colour;
        }
      }
    }
  }

  // Averages each kSupersampling^2 block into one ARGB32 pixel of `out`.
  void resolve(cairo_surface_t* out) const {
    cairo_surface_flush(out);
    unsigned char* data = cairo_image_surface_get_data(out);
    const int stride = cairo_image_surface_get_stride(out);
    const int w = size_ / kSupersampling;
    for (int y = 0; y < w; ++y) {
      auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
      for (int x = 0; x < w; ++x) {
        float sum[3] = {0, 0, 0};
        for (int j = 0; j < kSupersampling; ++j)
          for (int i = 0; i < kSupersampling; ++i) {
            const auto& c = rgb_[static_cast<std::size_t>(y * kSupersampling + j) * size_ + x * kSupersampling + i];
            for (int a = 0; a < 3; ++a) sum[a] += c[a];
          }
        auto channel = [&](int a) {
          return static_cast<std::uint32_t>(std::lround(255.0f * sum[a] / (kSupersampling * kSupersampling)));
        };
        row[x] = 0xff000000u | (channel(0) << 16) | (channel(1) << 8) | channel(2);
      }
    }
    cairo_surface_mark_dirty(out);
  }

 private:
  // The part of the ray through sample (x, y) inside the sphere is [back, front] in
  // depth; inside the box it is [exit, entry]. The visible point is the nearer end of
  // their overlap: the sphere's surface, or the box face where the ray enters (then
  // `front` and `normal` become the face's). False when they do not overlap.
  bool cut_by_box(int x, int y, double& front, double back, double length, Vec<3>& normal) const {
    const Vec<3> p = world_at(x, y);
    double entry = std::numeric_limits<double>::infinity(), exit = -entry;
    int entry_axis = -1;
    for (int a = 0; a < 3; ++a) {
      const double w = cam_.back[a];
      if (std::abs(w) < 1e-12) {
        if (p[a] < 0.0 || p[a] > length) return false;
        continue;
      }
      const double t0 = (0.0 - p[a]) / w, t1 = (length - p[a]) / w;
      const double hi = std::max(t0, t1), lo = std::min(t0, t1);
      if (hi < entry) { entry = hi; entry_axis = a; }
      exit = std::max(exit, lo);
    }
    if (std::max(back, exit) > std::min(front, entry)) return false;
    if (front > entry) {
      front = entry;
      Vec<3> n = Vec<3>::Zero();
      n[entry_axis] = cam_.back[entry_axis] > 0.0 ? 1.0 : -1.0;  // the face looking at the viewer
      normal = {n.dot(cam_.right), n.dot(cam_.up), n.dot(cam_.back)};
    }
    return true;
  }

  int size_;
  CameraFrame cam_;
  Vec<3> origin_;
  double scale_;
  std::vector<float> depth_;
  std::vector<std::array<float, 3>> rgb_;
};

}  // namespace

double draw_spheres(cairo_t* cr, const Scene<3>& s, const Layout& l, const View3& view) {
  const CameraFrame cam(view.towards_viewer);
  const Vec<3> light = view.light.normalized();
  const double length = s.box.length;
  // Frame what is shown: the box's corners, or the aggregate's spheres.
  double lo_u = 1e300, hi_u = -1e300, lo_v = 1e300, hi_v = -1e300;
  auto extend = [&](const Vec<3>& p, double r) {
    lo_u = std::min(lo_u, p.dot(cam.right) - r);
    hi_u = std::max(hi_u, p.dot(cam.right) + r);
    lo_v = std::min(lo_v, p.dot(cam.up) - r);
    hi_v = std::max(hi_v, p.dot(cam.up) + r);
  };
  if (s.whole_box) {
    for (int k = 0; k < 8; ++k) extend(Vec<3>((k & 1) * length, ((k >> 1) & 1) * length, ((k >> 2) & 1) * length), 0.0);
  } else {
    for (int i = 0; i < s.size(); ++i) extend(s.centre[i], s.radius[i]);
  }
  const double span = std::max(hi_u - lo_u, hi_v - lo_v) * 1.04;
  const int panel = static_cast<int>(l.side);
  const int size = panel * kSupersampling;
  const double scale = size / span;
  const double cu = 0.5 * (lo_u + hi_u), cv = 0.5 * (lo_v + hi_v);
  // Depth 0 somewhere in front of everything; the screen's top left corner.
  const Vec<3> origin = (cu - 0.5 * span) * cam.right + (cv + 0.5 * span) * cam.up;
  Raster raster(size, cam, origin, scale);
  const SphereShading shading;
  for (int i = 0; i < s.size(); ++i) {
    const Vec<3>& c = s.centre[i];
    const double r = s.radius[i];
    const Rgb& colour = kClusterColours[s.colour[i]];
    if (!s.periodic_images()) {
      raster.sphere(c, r, colour, light, shading, -1.0);
      continue;
    }
    // Every image that reaches into the box, each cut by the faces.
    std::array<std::array<double, 2>, 3> shifts{};
    std::array<int, 3> counts{1, 1, 1};
    for (int a = 0; a < 3; ++a) {
      if (c[a] - r < 0.0) shifts[a][counts[a]++] = length;
      else if (c[a] + r > length) shifts[a][counts[a]++] = -length;
    }
    const bool crosses = counts[0] + counts[1] + counts[2] > 3;
    for (int i0 = 0; i0 < counts[0]; ++i0)
      for (int i1 = 0; i1 < counts[1]; ++i1)
        for (int i2 = 0; i2 < counts[2]; ++i2)
          raster.sphere(c + Vec<3>(shifts[0][i0], shifts[1][i1], shifts[2][i2]), r, colour, light, shading,
                        crosses ? length : -1.0);
  }
  if (s.whole_box) {
    const double width = std::max(1.0, 0.0025 * panel) * kSupersampling;
    for (int k = 0; k < 8; ++k)
      for (int a = 0; a < 3; ++a) {
        if ((k >> a) & 1) continue;
        const Vec<3> p((k & 1) * length, ((k >> 1) & 1) * length, ((k >> 2) & 1) * length);
        Vec<3> q = p;
        q[a] = length;
        raster.segment(p, q, width, {0.1f, 0.1f, 0.1f}, 0.5 * s.mean_radius);
      }
  }
  cairo_surface_t* image = cairo_image_surface_create(CAIRO_FORMAT_RGB24, panel, panel);
  raster.resolve(image);
  cairo_save(cr);
  cairo_set_source_surface(cr, image, l.margin, l.margin);
  cairo_paint(cr);
  cairo_restore(cr);
  cairo_surface_destroy(image);
  return scale / kSupersampling;
}

}  // namespace ballagg
