// A picture under construction: colours and, per pixel, the distance along the pixel's ray of what is
// drawn there (the first surface, or a marker in front of it). Markers are ray-cast spheres and sampled
// lines, each depth-tested against it, so probes behind a wall stay hidden.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/eval/reference.h"

namespace probebake::render::detail {

struct Canvas {
  bake::Image image;
  std::vector<float> depth; // +inf where the pixel's ray meets nothing

  // Draws the sphere (centre, radius) where it is nearer than what the canvas holds; `colour` gets the
  // sphere's unit outward normal at the visible point. Spheres the camera is inside or behind are skipped.
  void sphere(const bake::CameraFrame& frame, glm::vec3 centre, float radius,
              const std::function<glm::vec3(glm::vec3)>& colour);
  // A segment from a to b, one pixel wide, in front of what the canvas holds.
  void line(const bake::CameraFrame& frame, glm::vec3 a, glm::vec3 b, glm::vec3 colour);
};

} // namespace probebake::render::detail
