#include "ballagg/render/picture.hpp"

#include <cairo-svg.h>

#include <filesystem>

#include <fmt/format.h>

#include "ballagg/io/output_dir.hpp"
#include "ballagg/io/output_error.hpp"
#include "ballagg/render/disc_picture.hpp"

namespace ballagg {

namespace {

template <int D>
Caption caption_of(const Scene<D>& s) {
  Caption c;
  if (s.whole_box) {
    c.title = fmt::format("t = {:.6g}", s.time);
  } else {
    c.title = fmt::format("t = {:.6g}   aggregate {} by size{}: {} spheres", s.time, s.aggregate_rank,
                          s.aggregate_rank == 1 ? " (the largest)" : "", grouped(s.shown_cluster_size));
  }
  c.counts = fmt::format("N = {}   clusters {}   largest {}", grouped(s.n_spheres), grouped(s.n_clusters),
                         grouped(s.largest));
  c.legend = s.whole_box;
  c.mean_diameter = 2.0 * s.mean_radius;
  return c;
}

// Renames a picture written to `temporary` into place, or removes it if cairo failed.
void commit_file(cairo_status_t status, const std::string& temporary, const std::string& path) {
  std::error_code ec;
  if (status != CAIRO_STATUS_SUCCESS) {
    std::filesystem::remove(temporary, ec);
    throw OutputError(fmt::format("{}: cannot write: {}", path, cairo_status_to_string(status)));
  }
  rename_into_place(temporary, path);
}

}  // namespace

template <int D>
void draw_picture(cairo_t* cr, const Scene<D>& s, const Layout& l, const PictureOptions& o) {
  cairo_set_source_rgb(cr, kBackground.r, kBackground.g, kBackground.b);
  cairo_paint(cr);
  Caption caption = caption_of(s);
  if constexpr (D == 2) {
    draw_discs(cr, s, l);
    caption.pixels_per_unit = panel_map(s, l).scale;
  } else {
    caption.pixels_per_unit = draw_spheres(cr, s, l, o.view);
  }
  draw_caption(cr, l, caption);
}

template <int D>
cairo_surface_t* render_image(const Scene<D>& s, const PictureOptions& o, cairo_format_t format) {
  const Layout l = make_layout(o.width);
  cairo_surface_t* surface = cairo_image_surface_create(format, l.width, l.height);
  cairo_t* cr = cairo_create(surface);
  draw_picture(cr, s, l, o);
  cairo_destroy(cr);
  cairo_surface_flush(surface);
  return surface;
}

template <int D>
void write_png(const Scene<D>& s, const PictureOptions& o, const std::string& path) {
  cairo_surface_t* surface = render_image(s, o, CAIRO_FORMAT_RGB24);
  const std::string temporary = fresh_temporary_for(path);
  const cairo_status_t status = cairo_surface_write_to_png(surface, temporary.c_str());
  cairo_surface_destroy(surface);
  commit_file(status, temporary, path);
}

template <int D>
void write_svg(const Scene<D>& s, const PictureOptions& o, const std::string& path) {
  const Layout l = make_layout(o.width);
  const std::string temporary = fresh_temporary_for(path);
  cairo_surface_t* surface = cairo_svg_surface_create(temporary.c_str(), l.width, l.height);
  cairo_t* cr = cairo_create(surface);
  draw_picture(cr, s, l, o);
  cairo_destroy(cr);
  cairo_surface_finish(surface);  // the SVG file is complete only now
  const cairo_status_t status = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  commit_file(status, temporary, path);
}

template void draw_picture<2>(cairo_t*, const Scene<2>&, const Layout&, const PictureOptions&);
template void draw_picture<3>(cairo_t*, const Scene<3>&, const Layout&, const PictureOptions&);
template cairo_surface_t* render_image<2>(const Scene<2>&, const PictureOptions&, cairo_format_t);
template cairo_surface_t* render_image<3>(const Scene<3>&, const PictureOptions&, cairo_format_t);
template void write_png<2>(const Scene<2>&, const PictureOptions&, const std::string&);
template void write_png<3>(const Scene<3>&, const PictureOptions&, const std::string&);
template void write_svg<2>(const Scene<2>&, const PictureOptions&, const std::string&);
template void write_svg<3>(const Scene<3>&, const PictureOptions&, const std::string&);

}  // namespace ballagg
