#pragma once
// 3D pictures: a depth-buffered renderer of shaded spheres in orthographic projection
// (lengths in the picture are true to scale, so the scale bar holds everywhere).
// Each pixel is sampled kSupersampling^2 times (antialiasing). A sphere is lit by one
// directional light (ambient + Lambert diffuse + Blinn-Phong highlight). In a periodic
// box, spheres crossing a face are drawn at their images too and cut by the box faces,
// the cut shaded as the face: the box looks like a solid block sliced from the periodic
// system. The box edges are drawn depth-tested (hidden where spheres are in front).
#include <cairo.h>

#include "ballagg/render/layout.hpp"
#include "ballagg/render/scene.hpp"

namespace ballagg {

inline constexpr int kSupersampling = 3;

// The widest 3D picture: the supersampled raster holds (kSupersampling x panel)^2 samples
// of 16 bytes (depth and colour), so the memory grows as the width squared: a few GB at
// this width, beyond a common machine's memory at the 2D limit (docs/performance.md,
// "Rendering"). 2D pictures go up to kMaxPictureWidth.
inline constexpr int kMaxSpherePictureWidth = 4096;

struct View3 {
  Vec<3> towards_viewer{1.0, -1.6, 1.0};  // world direction from the scene to the camera
  Vec<3> light{-0.45, 0.6, 0.75};         // in the picture's frame: x right, y up, z to the viewer
};

// The camera's frame: right, up, towards the viewer (world z is up unless we look along it).
struct CameraFrame {
  Vec<3> right, up, back;
  explicit CameraFrame(const Vec<3>& towards_viewer);
};

struct SphereShading {
  double ambient = 0.28, diffuse = 0.72, specular = 0.35, shininess = 40.0;
};

// Draws the scene into the layout's panel; returns the pixels per unit length.
double draw_spheres(cairo_t* cr, const Scene<3>& scene, const Layout& layout, const View3& view);

}  // namespace ballagg
