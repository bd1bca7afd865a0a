// Punctual lights per the KHR_lights_punctual specification (range window, spot cone falloff), glTF
// units taken as radiometric: candela = W/sr (point, spot), lux = W/m^2 (directional).
#include "direct_light.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "probebake/bake/lighting.h"

namespace probebake::bake {
namespace lighting_detail {

float range_window(float range, float distance) {
  if (!(range > 0.0f)) return 1.0f;
  const float q = distance / range;
  return std::clamp(1.0f - q * q * q * q, 0.0f, 1.0f);
}

float spot_falloff(const scene::Light& light, glm::vec3 light_to_point) {
  const float cos_outer = std::cos(light.outer_cone_angle);
  const float scale = 1.0f / std::max(0.001f, std::cos(light.inner_cone_angle) - cos_outer);
  const float a = std::clamp((glm::dot(light.direction, light_to_point) - cos_outer) * scale, 0.0f, 1.0f);
  return a * a;
}

DirectLighting::DirectLighting(const scene::Scene& scene, const scene::RayScene& rays) : scene_(scene), rays_(rays) {
  const glm::vec3 extent = scene.bounds.empty() ? glm::vec3(1.0f) : scene.bounds.max - scene.bounds.min;
  offset_ = 1e-4f * std::max({extent.x, extent.y, extent.z, 1e-30f});
}

glm::vec3 DirectLighting::irradiance(glm::vec3 position, glm::vec3 normal) const {
  glm::vec3 e(0.0f);
  for (const scene::Light& light : scene_.lights) e += from_light(light, position, normal);
  return e;
}

bool DirectLighting::visible(glm::vec3 origin, glm::vec3 target) const {
  const glm::vec3 to = target - origin;
  const float dist = glm::length(to);
  return !(dist > 0.0f) || !rays_.occluded(origin, to / dist, 0.0f, dist);
}

glm::vec3 DirectLighting::from_light(const scene::Light& light, glm::vec3 p, glm::vec3 n) const {
  if (light.intensity == 0.0f) return glm::vec3(0.0f);
  const glm::vec3 origin = p + n * offset_;
  const glm::vec3 power = light.color * light.intensity;
  if (light.type == scene::LightType::directional) {
    const glm::vec3 l = -light.direction;
    const float cosine = glm::dot(n, l);
    if (cosine <= 0.0f || rays_.occluded(origin, l, 0.0f, 3.0e38f)) return glm::vec3(0.0f);
    return power * cosine;
  }
  const glm::vec3 to = light.position - p;
  const float r2 = glm::dot(to, to);
  if (!(r2 > 0.0f)) return glm::vec3(0.0f); // the light sits on the point: no defined direction
  const float r = std::sqrt(r2);
  const glm::vec3 l = to / r;
  const float cosine = glm::dot(n, l);
  if (cosine <= 0.0f) return glm::vec3(0.0f);
  float attenuation = range_window(light.range, r) / r2;
  if (light.type == scene::LightType::spot) attenuation *= spot_falloff(light, -l);
  if (attenuation == 0.0f || !visible(origin, light.position)) return glm::vec3(0.0f);
  return power * (cosine * attenuation);
}

} // namespace lighting_detail

glm::vec3 direct_irradiance(const scene::Scene& scene, const scene::RayScene& rays, glm::vec3 position,
                            glm::vec3 normal) {
  return lighting_detail::DirectLighting(scene, rays).irradiance(position, normal);
}

} // namespace probebake::bake
