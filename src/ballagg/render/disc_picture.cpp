#include "ballagg/render/disc_picture.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ballagg {

PanelMap panel_map(const Scene<2>& s, const Layout& l) {
  const Vec<2> extent = s.hi - s.lo;
  const double span = std::max(extent[0], extent[1]) * (s.whole_box ? 1.0 : 1.05);
  const Vec<2> centre = 0.5 * (s.lo + s.hi);
  PanelMap m;
  m.scale = l.side / span;
  m.x0 = centre[0] - 0.5 * span;
  m.y0 = centre[1] - 0.5 * span;
  return m;
}

namespace {

void fill_disc(cairo_t* cr, double x, double y, double r_px, const Rgb& c) {
  if (r_px >= kMinRimRadiusPixels) {
    cairo_set_source_rgb(cr, kRimShade * c.r, kRimShade * c.g, kRimShade * c.b);
    cairo_arc(cr, x, y, r_px, 0.0, 2.0 * std::numbers::pi);
    cairo_fill(cr);
    r_px *= 1.0 - kRimFraction;
  }
  cairo_set_source_rgb(cr, c.r, c.g, c.b);
  cairo_arc(cr, x, y, r_px, 0.0, 2.0 * std::numbers::pi);
  cairo_fill(cr);
}

}  // namespace

void draw_discs(cairo_t* cr, const Scene<2>& s, const Layout& l) {
  const PanelMap m = panel_map(s, l);
  auto px = [&](double x) { return l.margin + (x - m.x0) * m.scale; };
  auto py = [&](double y) { return l.margin + l.side - (y - m.y0) * m.scale; };
  cairo_save(cr);
  cairo_rectangle(cr, l.margin, l.margin, l.side, l.side);
  cairo_clip(cr);
  const double length = s.box.length;
  for (int i = 0; i < s.size(); ++i) {
    const Vec<2>& c = s.centre[i];
    const double r = s.radius[i];
    const Rgb& colour = kClusterColours[s.colour[i]];
    // A disc crossing a periodic face shows on both sides: each axis contributes the
    // shift 0 and, when the disc crosses one of its faces, +L or -L.
    double shift_x[2] = {0.0, 0.0}, shift_y[2] = {0.0, 0.0};
    int nx = 1, ny = 1;
    if (s.periodic_images()) {
      if (c[0] - r < 0.0) shift_x[nx++] = length;
      else if (c[0] + r > length) shift_x[nx++] = -length;
      if (c[1] - r < 0.0) shift_y[ny++] = length;
      else if (c[1] + r > length) shift_y[ny++] = -length;
    }
    for (int a = 0; a < nx; ++a)
      for (int b = 0; b < ny; ++b) fill_disc(cr, px(c[0] + shift_x[a]), py(c[1] + shift_y[b]), r * m.scale, colour);
  }
  cairo_restore(cr);
  if (s.whole_box) {
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
    const double w = std::max(1.0, 0.0015 * l.side);
    cairo_set_line_width(cr, w);
    cairo_rectangle(cr, px(0.0) - 0.5 * w, py(length) - 0.5 * w, length * m.scale + w, length * m.scale + w);
    cairo_stroke(cr);
    cairo_restore(cr);
  }
}

}  // namespace ballagg
