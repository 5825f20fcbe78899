#pragma once
// A scene to a finished picture: the panel (2D discs with cairo, or 3D shaded spheres),
// the caption, and the output: PNG, SVG, or raw pixels for a video frame. Files are
// written to a temporary name and renamed, so a picture that exists is complete.
#include <cairo.h>

#include <string>

#include "ballagg/render/layout.hpp"
#include "ballagg/render/scene.hpp"
#include "ballagg/render/sphere_picture.hpp"

namespace ballagg {

struct PictureOptions {
  int width = 1200;  // pixels (the height follows from the layout)
  View3 view;        // 3D only
};

// Paints the whole page (background, panel, caption) on cr.
template <int D>
void draw_picture(cairo_t* cr, const Scene<D>& scene, const Layout& layout, const PictureOptions& options);

// Throws std::runtime_error naming the file if it cannot be written.
template <int D>
void write_png(const Scene<D>& scene, const PictureOptions& options, const std::string& path);
template <int D>
void write_svg(const Scene<D>& scene, const PictureOptions& options, const std::string& path);

// The page as an image surface (the caller destroys it): ARGB32 for video frames, RGB24
// for PNG files (three channels: smaller files, the page is opaque anyway).
template <int D>
cairo_surface_t* render_image(const Scene<D>& scene, const PictureOptions& options,
                              cairo_format_t format = CAIRO_FORMAT_ARGB32);

}  // namespace ballagg
