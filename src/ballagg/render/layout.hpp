#pragma once
// The page of a picture: a square panel with the scene on top, a caption band below it
// (time, counts, colour legend, scale bar). Shared by the 2D and 3D renderers, PNG, SVG
// and video frames.
#include <cairo.h>

#include <string>

namespace ballagg {

struct Layout {
  int width = 0, height = 0;  // pixels; both even (video encoders need that)
  double margin = 0.0;        // around the panel
  double side = 0.0;          // the square panel: [margin, margin + side]^2
  double caption_top = 0.0, caption_height = 0.0;
};

// Pictures narrower than this leave no room for the caption.
inline constexpr int kMinPictureWidth = 64;
inline constexpr int kMaxPictureWidth = 16384;

Layout make_layout(int width);

struct Caption {
  std::string title;          // e.g. "t = 123.4"
  std::string counts;         // e.g. "N = 10000   clusters 35   largest 8012"
  bool legend = true;         // red = largest, palette = others
  double pixels_per_unit = 1.0;
  double mean_diameter = 1.0; // the scale bar also reads in diameters
};

void draw_caption(cairo_t* cr, const Layout& layout, const Caption& caption);

// A length near `target` of the form 1, 2 or 5 times a power of ten.
double round_scale_length(double target);

// Thousands separated by thin spaces: 1000000 -> "1 000 000".
std::string grouped(long long n);

}  // namespace ballagg
