#pragma once
// A POV-Ray 3.7 scene of one aggregate (or the whole box) for a ray-traced picture like
// Richardson (1995), Fig. 12: perspective camera, a key light with soft shadows and a
// fill light, shiny spheres. Render it with
//   povray +W1200 +H1200 +A0.3 +Oaggregate.png aggregate.pov
// POV-Ray's frame is left-handed with y up: our (x, y, z) is written as <x, z, y>.
#include <string>

#include "ballagg/render/scene.hpp"
#include "ballagg/render/sphere_picture.hpp"

namespace ballagg {

std::string pov_scene_text(const Scene<3>& scene, const View3& view);

}  // namespace ballagg
