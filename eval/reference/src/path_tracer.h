// One path of the irradiance estimator: E(x) = integral of incoming radiance times cos over the
// hemisphere of n, traced through diffuse bounces.
#pragma once

#include "lights.h"
#include "probebake/eval/reference.h"
#include "rng.h"

namespace probebake::bake::detail {

struct PathContext {
  const scene::Scene* scene = nullptr;
  const scene::RayScene* rays = nullptr;
  const EmitterTable* emitters = nullptr;
  float epsilon = 1e-5f;   // ray origin offset along the normal
  int roulette_after = 3;
  int max_bounces = 100000;
};

// An unbiased estimate of the irradiance at `point` (one path, with next-event estimation at each vertex).
glm::vec3 irradiance_path(const PathContext& context, const SamplePoint& point, Pcg32& rng);

} // namespace probebake::bake::detail
