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
  float epsilon = 1e-5f; // ray origin offset along the normal
  int roulette_after = 3;
  int max_bounces = 100000;
};

// One path's estimate of the irradiance at the receiver, and the part of it that is direct light: the
// next-event samples at the receiver itself and the emission its first ray hits (what direct_irradiance
// computes in the bake; the rest is what probes hold).
struct PathEstimate {
  glm::vec3 total{0.0f};
  glm::vec3 direct{0.0f};
};

// An unbiased estimate of the irradiance at `point` (one path, with next-event estimation at each vertex).
PathEstimate irradiance_path(const PathContext& context, const SamplePoint& point, Pcg32& rng);

} // namespace probebake::bake::detail
