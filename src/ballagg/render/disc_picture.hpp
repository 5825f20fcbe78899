#pragma once
// 2D pictures with cairo: every disc drawn to scale in the box (y up), in its cluster's
// colour with a darker rim inside its edge (so that the discs of one cluster stay
// distinct), a disc crossing a periodic face also drawn at its images on the other
// side(s), clipped to the box; the box outline; the caption below.
#include <cairo.h>

#include "ballagg/render/layout.hpp"
#include "ballagg/render/scene.hpp"

namespace ballagg {

// Discs whose radius is at least this many pixels get a rim.
inline constexpr double kMinRimRadiusPixels = 3.0;
// Rim width as a fraction of the radius, and its shade as a fraction of the fill colour.
inline constexpr double kRimFraction = 0.12;
inline constexpr double kRimShade = 0.6;

struct PanelMap {
  double x0 = 0.0, y0 = 0.0;   // world point at the panel's lower left corner
  double scale = 1.0;          // pixels per unit length
};

// The region of the scene (a square around lo..hi) onto the layout's panel.
PanelMap panel_map(const Scene<2>& scene, const Layout& layout);

void draw_discs(cairo_t* cr, const Scene<2>& scene, const Layout& layout);

}  // namespace ballagg
