#include "lights.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "sampling.h"

namespace probebake::bake::detail {

float emission_weight(const glm::vec3& e) {
  return (std::max(e.x, 0.0f) + std::max(e.y, 0.0f) + std::max(e.z, 0.0f)) / 3.0f;
}

EmitterTable::EmitterTable(const scene::Scene& scene) : scene_(&scene), pdf_by_triangle_(scene.triangles.size(), 0.0f) {
  double total = 0.0;
  for (std::uint32_t t = 0; t < scene.triangles.size(); ++t) {
    const double power = scene::triangle_area(scene, t) * emission_weight(scene.triangle_emission[t]);
    if (!(power > 0.0)) continue;
    total += power;
    triangles_.push_back(t);
    cdf_.push_back(total);
  }
  for (double& c : cdf_) c /= total;
  if (!cdf_.empty()) cdf_.back() = 1.0;
  // Power-proportional choice times uniform area: weight_t / total = mean emission / total power.
  for (std::uint32_t t : triangles_)
    pdf_by_triangle_[t] = static_cast<float>(emission_weight(scene.triangle_emission[t]) / total);
}

float EmitterTable::pdf_area(std::uint32_t t) const { return pdf_by_triangle_[t]; }

EmitterTable::Sample EmitterTable::sample(Pcg32& rng) const {
  const double u = static_cast<double>(rng.uniform());
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const std::size_t i = std::min(static_cast<std::size_t>(it - cdf_.begin()), triangles_.size() - 1);
  const std::uint32_t t = triangles_[i];
  const glm::uvec3 tri = scene_->triangles[t];
  const float u1 = rng.uniform(), u2 = rng.uniform();
  return {t,
          uniform_triangle_point(scene_->positions[tri.x], scene_->positions[tri.y], scene_->positions[tri.z], u1, u2)};
}

namespace {

// KHR_lights_punctual: the recommended range window, clamp(1 - (d / range)^4, 0, 1); range 0 = infinite.
float range_window(float range, float dist) {
  if (range <= 0.0f) return 1.0f;
  const float r = dist / range;
  return std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
}

// KHR_lights_punctual spot falloff: smoothstep-like ramp between the outer and inner cone, squared.
float spot_falloff(const scene::Light& light, const glm::vec3& to_point) {
  const float cos_outer = std::cos(light.outer_cone_angle);
  const float cos_inner = std::cos(light.inner_cone_angle);
  const float scale = 1.0f / std::max(0.001f, cos_inner - cos_outer);
  const float cd = glm::dot(glm::normalize(light.direction), to_point);
  const float a = std::clamp((cd - cos_outer) * scale, 0.0f, 1.0f);
  return a * a;
}

// Shadow ray from `origin` (the point lifted off its surface) to `target`, unblocked?
bool visible(const scene::RayScene& rays, const glm::vec3& origin, const glm::vec3& target, float shorten) {
  const glm::vec3 d = target - origin;
  const float dist = glm::length(d);
  return !(dist > shorten) || !rays.occluded(origin, d / dist, 0.0f, dist - shorten);
}

// Geometry (distance, cosines) from the surface point x itself, so that the ray offset does not bias it.
glm::vec3 one_light(const scene::Light& light, const scene::RayScene& rays, const glm::vec3& x, const glm::vec3& n,
                    const glm::vec3& origin) {
  const glm::vec3 radiometric = light.color * light.intensity;
  if (light.type == scene::LightType::directional) {
    const glm::vec3 w = -glm::normalize(light.direction);
    const float cos_x = glm::dot(n, w);
    if (cos_x <= 0.0f || rays.occluded(origin, w, 0.0f, 3.0e38f)) return glm::vec3(0.0f);
    return radiometric * cos_x;
  }
  const glm::vec3 d = light.position - x;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return glm::vec3(0.0f); // a light on the point has no direction
  const float dist = std::sqrt(dist2);
  const glm::vec3 w = d / dist;
  const float cos_x = glm::dot(n, w);
  if (cos_x <= 0.0f) return glm::vec3(0.0f);
  float falloff = range_window(light.range, dist);
  if (light.type == scene::LightType::spot) falloff *= spot_falloff(light, -w);
  if (falloff <= 0.0f || !visible(rays, origin, light.position, 0.0f)) return glm::vec3(0.0f);
  return radiometric * (falloff * cos_x / dist2);
}

} // namespace

glm::vec3 punctual_irradiance(const scene::Scene& scene, const scene::RayScene& rays, const glm::vec3& x,
                              const glm::vec3& n, float epsilon) {
  glm::vec3 e(0.0f);
  for (const scene::Light& light : scene.lights)
    if (light.intensity > 0.0f) e += one_light(light, rays, x, n, x + epsilon * n);
  return e;
}

glm::vec3 emitter_irradiance_sample(const scene::Scene& scene, const scene::RayScene& rays,
                                    const EmitterTable& emitters, const glm::vec3& x, const glm::vec3& n, float epsilon,
                                    Pcg32& rng) {
  if (emitters.empty()) return glm::vec3(0.0f);
  const EmitterTable::Sample s = emitters.sample(rng);
  const glm::vec3 d = s.position - x;
  const float dist2 = glm::dot(d, d);
  const float dist = std::sqrt(dist2);
  if (!(dist > epsilon)) return glm::vec3(0.0f);
  const glm::vec3 w = d / dist;
  const float cos_x = glm::dot(n, w);
  // Emitters shine from the front; double-sided ones (glTF doubleSided) from both sides, |cos| at the emitter.
  const float cos_front = -glm::dot(scene::triangle_normal(scene, s.triangle), w);
  const float cos_y = scene::is_double_sided(scene, s.triangle) ? std::abs(cos_front) : cos_front;
  if (cos_x <= 0.0f || cos_y <= 0.0f) return glm::vec3(0.0f);
  if (!visible(rays, x + epsilon * n, s.position, epsilon)) return glm::vec3(0.0f);
  const float pdf_light = emitters.pdf_area(s.triangle) * dist2 / cos_y; // solid angle at origin
  const float pdf_bsdf = cos_x / kPi;
  return scene.triangle_emission[s.triangle] * (cos_x / pdf_light * power_heuristic(pdf_light, pdf_bsdf));
}

float bsdf_hit_weight(const EmitterTable& emitters, std::uint32_t t, float cos_x, float dist, float cos_y) {
  const float pdf_area = emitters.pdf_area(t);
  if (pdf_area <= 0.0f || cos_y <= 0.0f) return 1.0f; // never chosen by next-event estimation
  return power_heuristic(cos_x / kPi, pdf_area * dist * dist / cos_y);
}

} // namespace probebake::bake::detail
