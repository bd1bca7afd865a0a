// Direct irradiance from KHR_lights_punctual lights with Embree shadow rays (lighting.h describes the
// model). Built once per scene; irradiance() is thread-safe.
#pragma once

#include <glm/vec3.hpp>

#include "probebake/bake/ray_scene.h"
#include "probebake/bake/scene.h"

namespace probebake::bake::lighting_detail {

class DirectLighting {
public:
  DirectLighting(const scene::Scene& scene, const scene::RayScene& rays);
  // Sum over the scene's lights at a surface point with unit normal `normal`.
  glm::vec3 irradiance(glm::vec3 position, glm::vec3 normal) const;

private:
  glm::vec3 from_light(const scene::Light& light, glm::vec3 position, glm::vec3 normal) const;
  bool visible(glm::vec3 origin, glm::vec3 target) const;

  const scene::Scene& scene_;
  const scene::RayScene& rays_;
  float offset_; // shadow-ray origin offset along the normal: 1e-4 of the scene's largest extent
};

// KHR_lights_punctual's range window, clamp(1 - (r / range)^4, 0, 1); 1 for range <= 0.
float range_window(float range, float distance);
// KHR_lights_punctual's spot falloff for a light travelling along unit `spot_direction` towards unit
// `light_to_point`: smooth between the outer and inner cone, squared.
float spot_falloff(const scene::Light& light, glm::vec3 light_to_point);

} // namespace probebake::bake::lighting_detail
