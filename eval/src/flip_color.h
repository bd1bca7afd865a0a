// FLIP's colour spaces (HPG 2020, colour pipeline): linear sRGB, CIE XYZ under D65, the opponent space
// YCxCz in which the contrast sensitivity filters act, and Hunt-adjusted CIE L*a*b* in which HyAB measures colour
// differences.
#pragma once

#include <cmath>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace probebake::bake::flip {

struct ColorSpaces {
  glm::mat3 rgb_to_xyz{1.0f};
  glm::mat3 xyz_to_rgb{1.0f};
  glm::vec3 white{1.0f}; // XYZ of linear RGB (1, 1, 1), Y = 1: the reference white of YCxCz and L*a*b*
};

// Built once from the sRGB primaries and D65 white point of IEC 61966-2-1.
const ColorSpaces& color_spaces();

// YCxCz (as HPG 2020 defines it): L*a*b* without the cube root, so it is linear in XYZ and filtering there
// is meaningful. Y = 116 Y/Yn - 16, Cx = 500 (X/Xn - Y/Yn), Cz = 200 (Y/Yn - Z/Zn).
inline glm::vec3 linear_to_ycxcz(glm::vec3 rgb) {
  const ColorSpaces& c = color_spaces();
  const glm::vec3 n = (c.rgb_to_xyz * rgb) / c.white;
  return {116.0f * n.y - 16.0f, 500.0f * (n.x - n.y), 200.0f * (n.y - n.z)};
}

inline glm::vec3 ycxcz_to_linear(glm::vec3 o) {
  const ColorSpaces& c = color_spaces();
  const float y = (o.x + 16.0f) / 116.0f;
  const glm::vec3 n(y + o.y / 500.0f, y, y - o.z / 200.0f);
  return c.xyz_to_rgb * (n * c.white);
}

// CIE 1976 L*a*b* with its linear segment below (6/29)^3.
inline float lab_f(float t) {
  constexpr float delta = 6.0f / 29.0f;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3.0f * delta * delta) + 4.0f / 29.0f;
}

inline glm::vec3 linear_to_lab(glm::vec3 rgb) {
  const ColorSpaces& c = color_spaces();
  const glm::vec3 n = (c.rgb_to_xyz * rgb) / c.white;
  const float fx = lab_f(n.x), fy = lab_f(n.y), fz = lab_f(n.z);
  return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

// Hunt effect (HPG 2020, colour pipeline): chroma looks weaker in darker colours; a*, b* scaled by 0.01 L*.
inline glm::vec3 hunt_adjust(glm::vec3 lab) { return {lab.x, 0.01f * lab.x * lab.y, 0.01f * lab.x * lab.z}; }

// HyAB (Abasi et al. 2020, as HPG 2020 uses it): city-block in lightness plus Euclidean in the chroma plane,
// which suits large colour differences better than Euclidean L*a*b*.
inline float hyab(glm::vec3 a, glm::vec3 b) {
  const glm::vec3 d = a - b;
  return std::fabs(d.x) + std::sqrt(d.y * d.y + d.z * d.z);
}

} // namespace probebake::bake::flip
