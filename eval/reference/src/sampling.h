// Sampling helpers of the reference path tracer: orthonormal bases, cosine-weighted hemisphere
// directions, uniform points on triangles, the power heuristic, and the ray offset used against
// self-intersection.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "probebake/scene/scene.h"

namespace probebake::bake::detail {

inline constexpr float kPi = std::numbers::pi_v<float>;

// Branchless orthonormal basis around unit n (Duff et al. 2017).
inline void orthonormal_basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
}

// Direction with density cos(theta) / pi about unit n (Malley: uniform disk point lifted to the hemisphere).
inline glm::vec3 cosine_hemisphere(const glm::vec3& n, float u1, float u2) {
  glm::vec3 t, b;
  orthonormal_basis(n, t, b);
  const float r = std::sqrt(u1);
  const float phi = 2.0f * kPi * u2;
  const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
  return glm::normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * z);
}

// Uniform point on triangle (a, b, c).
inline glm::vec3 uniform_triangle_point(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, float u1,
                                        float u2) {
  const float su = std::sqrt(u1);
  const float w0 = 1.0f - su, w1 = u2 * su;
  return w0 * a + w1 * b + (1.0f - w0 - w1) * c;
}

// Power heuristic (beta = 2) weight of the strategy with density pdf_a against pdf_b.
inline float power_heuristic(float pdf_a, float pdf_b) {
  const float a2 = pdf_a * pdf_a, b2 = pdf_b * pdf_b;
  return a2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

inline glm::vec3 triangle_point(const scene::Scene& scene, std::uint32_t t, float u, float v) {
  const glm::uvec3 tri = scene.triangles[t];
  return (1.0f - u - v) * scene.positions[tri.x] + u * scene.positions[tri.y] + v * scene.positions[tri.z];
}

} // namespace probebake::bake::detail
