#include "flip_color.h"

#include <glm/matrix.hpp>

namespace probebake::bake::flip {
namespace {

// CIE xy chromaticity as XYZ with Y = 1.
glm::dvec3 xyz_of(double x, double y) { return {x / y, 1.0, (1.0 - x - y) / y}; }

ColorSpaces make_color_spaces() {
  // IEC 61966-2-1 (sRGB): primaries R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06), white D65 (0.3127, 0.3290).
  const glm::dmat3 primaries(xyz_of(0.64, 0.33), xyz_of(0.30, 0.60), xyz_of(0.15, 0.06)); // columns
  const glm::dvec3 scale = glm::inverse(primaries) * xyz_of(0.3127, 0.3290);
  const glm::dmat3 m(primaries[0] * scale.x, primaries[1] * scale.y, primaries[2] * scale.z);
  ColorSpaces c;
  c.rgb_to_xyz = glm::mat3(m);
  c.xyz_to_rgb = glm::mat3(glm::inverse(m));
  c.white = glm::vec3(m * glm::dvec3(1.0));
  return c;
}

} // namespace

const ColorSpaces& color_spaces() {
  static const ColorSpaces spaces = make_color_spaces();
  return spaces;
}

} // namespace probebake::bake::flip
