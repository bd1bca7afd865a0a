// Direct irradiance at a surface point: KHR_lights_punctual lights with Embree shadow rays and, with
// LightingSettings::emissive_as_lights, the scene's emissive triangles as area lights (lighting.h
// describes both models). Built once per scene; irradiance() is thread-safe.
// Public to probebake_lighting's users because the runtime lighting sections (bake/src/gpu_scene.cpp) write
// the same lights, spot cones and emitter patches for the GPU.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/lighting/lighting.h"
#include "probebake/scene/ray_scene.h"
#include "probebake/scene/scene.h"

namespace probebake::lighting::detail {

// One piece of an emissive triangle: the sub-triangles of emitter_patches() are lit as area lights.
struct EmitterPatch {
  glm::vec3 a{0.0f}, b{0.0f}, c{0.0f}; // counter-clockwise seen from the emitting (front) side
  glm::vec3 normal{0.0f};              // unit, towards the front side
  glm::vec3 radiance{0.0f};            // emitted radiance, W/(m^2 sr)
  // glTF doubleSided material: emits the same radiance from both sides (|cos| at the emitter); a
  // single-sided patch lights nothing behind its plane.
  bool double_sided = false;
  std::uint32_t material = 0; // the emissive triangle's (scene.triangle_material): the runtime switches it
};

// The emissive triangles (emission > 0 in some channel, area > 0), in triangle order, each split into
// k^2 congruent sub-triangles (k - 1 cuts parallel to each edge), k = max(1, floor(sqrt(samples * P_t / P))),
// P_t = area * max channel of the emission, P = sum of P_t. Row-major in barycentric (i, j) order.
std::vector<EmitterPatch> emitter_patches(const scene::Scene& scene, int samples);

// Unoccluded irradiance at `p` with unit normal `n` from a patch, and the point the shadow ray aims at
// (centroid of the patch clipped to n's hemisphere). Returns false when `p` lies in the patch's plane or
// behind a single-sided patch, or when no vertex of the patch rises more than plane_margin above p's
// horizon, dot(n, vertex - p) <= plane_margin (p on the emitter itself; the bake passes shadow_offset).
// Behind a double-sided patch the result equals the one in front (the formula integrates |cos| at the
// emitter).
bool patch_irradiance(const EmitterPatch& patch, glm::vec3 p, glm::vec3 n, float plane_margin, glm::vec3& irradiance,
                      glm::vec3& target);

class DirectLighting {
public:
  DirectLighting(const scene::Scene& scene, const scene::RayScene& rays, const LightingSettings& settings);
  // Sum over the scene's punctual lights (and emitter patches when enabled) at a surface point.
  glm::vec3 irradiance(glm::vec3 position, glm::vec3 normal) const;

private:
  glm::vec3 from_light(const scene::Light& light, glm::vec3 position, glm::vec3 normal) const;
  glm::vec3 from_emitters(glm::vec3 position, glm::vec3 normal) const;
  bool visible(glm::vec3 origin, glm::vec3 target) const;

  const scene::Scene& scene_;
  const scene::RayScene& rays_;
  float offset_;                      // shadow_offset(scene): along the normal, for every shadow ray
  std::vector<EmitterPatch> patches_; // empty unless emissive_as_lights
};

// Shadow-ray origin offset along the normal: 1e-4 of the scene's largest extent (1e-4 for an empty
// scene). One definition for the bake's shadow rays and the runtime's (LightingInfo::shadow_offset).
float shadow_offset(const scene::Scene& scene);

// The spot cone as spot_falloff uses it, in float: cos(outer cone angle) and 1 / max(0.001, cos(inner) -
// cos(outer)). The runtime gets exactly these values (PunctualLight::cos_outer, spot_scale).
struct SpotCone {
  float cos_outer = 0.0f;
  float scale = 0.0f;
};
SpotCone spot_cone(const scene::Light& light);

// KHR_lights_punctual's range window, clamp(1 - (r / range)^4, 0, 1); 1 for range <= 0.
float range_window(float range, float distance);
// KHR_lights_punctual's spot falloff for a light travelling along unit `spot_direction` towards unit
// `light_to_point`: smooth between the outer and inner cone, squared.
float spot_falloff(const scene::Light& light, glm::vec3 light_to_point);

} // namespace probebake::lighting::detail
