#include "ballagg/render/layout.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "ballagg/render/colours.hpp"

namespace ballagg {

Layout make_layout(int width) {
  Layout l;
  l.width = width + (width % 2);
  l.margin = std::max(4.0, std::round(0.02 * l.width));
  l.side = l.width - 2.0 * l.margin;
  l.caption_top = l.margin + l.side;
  l.caption_height = std::max(36.0, std::round(0.085 * l.width));
  l.height = static_cast<int>(l.caption_top + l.caption_height);
  l.height += l.height % 2;
  l.caption_height = l.height - l.caption_top;
  return l;
}

double round_scale_length(double target) {
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  const double mantissa = target / decade;
  return decade * (mantissa < 1.5 ? 1.0 : mantissa < 3.5 ? 2.0 : mantissa < 7.5 ? 5.0 : 10.0);
}

std::string grouped(long long n) {
  std::string digits = fmt::format("{}", n < 0 ? -n : n), out;
  for (std::size_t k = 0; k < digits.size(); ++k) {
    if (k > 0 && (digits.size() - k) % 3 == 0) out += "\u2009";
    out += digits[k];
  }
  return (n < 0 ? "-" : "") + out;
}

namespace {

void set_colour(cairo_t* cr, const Rgb& c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

double text_width(cairo_t* cr, const std::string& s) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

}  // namespace

void draw_caption(cairo_t* cr, const Layout& l, const Caption& c) {
  cairo_save(cr);
  const double font = std::max(9.0, 0.24 * l.caption_height);
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, font);
  const double x0 = l.margin, line1 = l.caption_top + 0.40 * l.caption_height,
               line2 = l.caption_top + 0.80 * l.caption_height;
  set_colour(cr, {0, 0, 0});
  cairo_move_to(cr, x0, line1);
  cairo_show_text(cr, c.title.c_str());
  cairo_move_to(cr, x0, line2);
  cairo_show_text(cr, c.counts.c_str());

  // Scale bar at the right: a bar of a round length, labelled in box units and diameters.
  const double target_px = 0.22 * l.side;
  const double length = round_scale_length(target_px / c.pixels_per_unit);
  const double bar_px = length * c.pixels_per_unit;
  const double right = l.margin + l.side;
  const double bar_y = line1 - 0.3 * font;
  cairo_rectangle(cr, right - bar_px, bar_y, bar_px, std::max(2.0, 0.18 * font));
  cairo_fill(cr);
  const std::string label = fmt::format("{:g}  ({:g} diameters)", length, length / c.mean_diameter);
  cairo_move_to(cr, right - std::max(bar_px, text_width(cr, label)), line2);
  cairo_show_text(cr, label.c_str());

  if (c.legend) {
    // Legend between the counts and the scale bar: a red swatch, then the palette.
    const double sw = 0.55 * font;
    double x = x0 + std::max(text_width(cr, c.title), text_width(cr, c.counts)) + 1.5 * font;
    const std::string largest = "largest cluster", others = "others";
    const double needed = 4 * sw + text_width(cr, largest) + text_width(cr, others) + kPaletteSize * sw * 0.6;
    if (x + needed < right - std::max(bar_px, text_width(cr, label)) - font) {
      const double y = line1 - sw;
      set_colour(cr, kClusterColours[0]);
      cairo_rectangle(cr, x, y, sw, sw);
      cairo_fill(cr);
      set_colour(cr, {0, 0, 0});
      cairo_move_to(cr, x + 1.4 * sw, line1);
      cairo_show_text(cr, largest.c_str());
      const double y2 = line2 - sw;
      for (int k = 1; k <= kPaletteSize; ++k) {
        set_colour(cr, kClusterColours[k]);
        cairo_rectangle(cr, x + (k - 1) * sw * 0.6, y2, sw * 0.6, sw);
        cairo_fill(cr);
      }
      set_colour(cr, {0, 0, 0});
      cairo_move_to(cr, x + kPaletteSize * sw * 0.6 + 0.6 * sw, line2);
      cairo_show_text(cr, others.c_str());
    }
  }
  cairo_restore(cr);
}

}  // namespace ballagg
