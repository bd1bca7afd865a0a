// Punctual lights per the KHR_lights_punctual specification (range window, spot cone falloff), glTF
// units taken as radiometric: candela = W/sr (point, spot), lux = W/m^2 (directional). Emissive
// triangles as area lights: fixed sub-triangles, each with its exact unoccluded irradiance (Lambert's
// polygon formula after clipping to the point's hemisphere) times one shadow ray.
#include "probebake/lighting/direct_light.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "probebake/lighting/lighting.h"

namespace probebake::lighting {
namespace detail {

float range_window(float range, float distance) {
  if (!(range > 0.0f)) return 1.0f;
  const float q = distance / range;
  return std::clamp(1.0f - q * q * q * q, 0.0f, 1.0f);
}

SpotCone spot_cone(const scene::Light& light) {
  SpotCone cone;
  cone.cos_outer = std::cos(light.outer_cone_angle);
  cone.scale = 1.0f / std::max(0.001f, std::cos(light.inner_cone_angle) - cone.cos_outer);
  return cone;
}

float spot_falloff(const scene::Light& light, glm::vec3 light_to_point) {
  const SpotCone cone = spot_cone(light);
  const float a = std::clamp((glm::dot(light.direction, light_to_point) - cone.cos_outer) * cone.scale, 0.0f, 1.0f);
  return a * a;
}

float shadow_offset(const scene::Scene& scene) {
  const glm::vec3 extent = scene.bounds.empty() ? glm::vec3(1.0f) : scene.bounds.max - scene.bounds.min;
  return 1e-4f * std::max({extent.x, extent.y, extent.z, 1e-30f});
}

std::vector<EmitterPatch> emitter_patches(const scene::Scene& scene, int samples) {
  std::vector<std::size_t> emitters;
  std::vector<double> power;
  double total = 0.0;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const glm::vec3 e = scene.triangle_emission[t];
    const double area = scene::triangle_area(scene, t);
    if (!(std::max({e.x, e.y, e.z}) > 0.0f) || !(area > 0.0)) continue;
    emitters.push_back(t);
    power.push_back(area * double(std::max({e.x, e.y, e.z})));
    total += power.back();
  }
  std::vector<EmitterPatch> patches;
  for (std::size_t i = 0; i < emitters.size(); ++i) {
    const std::size_t t = emitters[i];
    const double share = total > 0.0 ? double(samples) * power[i] / total : 1.0;
    const int k = std::clamp(int(std::floor(std::sqrt(share))), 1, 64);
    const glm::uvec3 tri = scene.triangles[t];
    const glm::vec3 a = scene.positions[tri.x], ab = scene.positions[tri.y] - a, ac = scene.positions[tri.z] - a;
    const auto at = [&](int u, int v) { return a + (float(u) / float(k)) * ab + (float(v) / float(k)) * ac; };
    const glm::vec3 normal = scene::triangle_normal(scene, t), radiance = scene.triangle_emission[t];
    const bool double_sided = scene::is_double_sided(scene, t);
    const std::uint32_t material = scene.triangle_material[t];
    for (int u = 0; u < k; ++u)
      for (int v = 0; u + v < k; ++v) {
        patches.push_back({at(u, v), at(u + 1, v), at(u, v + 1), normal, radiance, double_sided, material});
        if (u + v < k - 1)
          patches.push_back({at(u + 1, v), at(u + 1, v + 1), at(u, v + 1), normal, radiance, double_sided, material});
      }
  }
  return patches;
}

bool patch_irradiance(const EmitterPatch& patch, glm::vec3 p, glm::vec3 n, float plane_margin, glm::vec3& irradiance,
                      glm::vec3& target) {
  // In the emitter's plane: nothing; behind it: nothing unless it emits from both sides. Lambert's formula
  // below does not depend on the polygon's winding, so the back of a double-sided patch needs no flip.
  const float side = glm::dot(p - patch.a, patch.normal);
  if (!(side > 0.0f) && !(patch.double_sided && side < 0.0f)) return false;
  // Sutherland-Hodgman against the plane dot(n, q) = 0 (q relative to p): at most 4 vertices.
  const glm::vec3 in[3] = {patch.a - p, patch.b - p, patch.c - p};
  glm::vec3 q[4];
  int count = 0;
  float highest = -3.0e38f; // max over the vertices of dot(n, q): how far the patch rises above p's horizon
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 s = in[i], e = in[(i + 1) % 3];
    const float ds = glm::dot(n, s), de = glm::dot(n, e);
    highest = std::max(highest, ds);
    if (ds >= 0.0f) q[count++] = s;
    if ((ds >= 0.0f) != (de >= 0.0f)) q[count++] = s + (e - s) * (ds / (ds - de));
  }
  // A patch that lies within plane_margin of p's tangent plane gives nothing: p is on the emitter itself
  // (a probe ray's hit on the light, a pixel of it) or on a surface coplanar with it, where `side` is
  // rounding noise of either sign and Lambert's formula is singular (it would give pi L). A point near the
  // emitter's plane on a surface that faces it (a wall meeting an emitting floor) keeps its light.
  if (count < 3 || !(highest > plane_margin)) return false;
  // Lambert's formula: integral over the polygon of cos = 1/2 |sum over edges of angle * dot(n, edge normal)|.
  double sum = 0.0;
  glm::vec3 centre(0.0f);
  for (int i = 0; i < count; ++i) {
    const glm::vec3 s = q[i], e = q[(i + 1) % count];
    centre += s;
    const glm::vec3 c = glm::cross(s, e);
    const float length = glm::length(c);
    if (!(length > 0.0f)) continue;
    sum += double(std::atan2(length, glm::dot(s, e))) * double(glm::dot(n, c) / length);
  }
  const float form = float(0.5 * std::abs(sum)); // projected solid angle
  if (!(form > 0.0f)) return false;
  irradiance = patch.radiance * form;
  target = p + centre / float(count);
  return true;
}

DirectLighting::DirectLighting(const scene::Scene& scene, const scene::RayScene& rays, const LightingSettings& settings)
    : scene_(scene), rays_(rays), offset_(shadow_offset(scene)) {
  if (settings.emissive_as_lights) patches_ = emitter_patches(scene, settings.emitter_samples);
}

glm::vec3 DirectLighting::irradiance(glm::vec3 position, glm::vec3 normal) const {
  glm::vec3 e(0.0f);
  for (const scene::Light& light : scene_.lights) e += from_light(light, position, normal);
  if (!patches_.empty()) e += from_emitters(position, normal);
  return e;
}

glm::vec3 DirectLighting::from_emitters(glm::vec3 p, glm::vec3 n) const {
  const glm::vec3 origin = p + n * offset_;
  glm::vec3 e(0.0f), patch_e, target;
  for (const EmitterPatch& patch : patches_) {
    if (!patch_irradiance(patch, p, n, offset_, patch_e, target)) continue;
    const glm::vec3 to = target - origin;
    const float dist = glm::length(to);
    // Stop short of the emitter itself (a relative 1e-3 of the distance).
    if (dist > 0.0f && rays_.occluded(origin, to / dist, 0.0f, dist * 0.999f)) continue;
    e += patch_e;
  }
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

} // namespace detail

glm::vec3 direct_irradiance(const scene::Scene& scene, const scene::RayScene& rays, glm::vec3 position,
                            glm::vec3 normal, const LightingSettings& settings) {
  return detail::DirectLighting(scene, rays, settings).irradiance(position, normal);
}

} // namespace probebake::lighting
