#include "path_tracer.h"

#include <algorithm>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "sampling.h"

namespace probebake::bake::detail {
namespace {

float max_component(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

// Survival probability of Russian roulette: the path's throughput, so that surviving paths carry weight
// ~1 (pbrt-v4); capped below 1 so that paths end even in a furnace of albedo 1.
float survival_probability(const glm::vec3& throughput) { return std::min(0.999f, max_component(throughput)); }

} // namespace

// Vertex k's irradiance enters the estimate with weight beta_k = product of the albedos of the k surfaces
// before it (cosine sampling cancels cos / pi against the pdf), divided by the roulette survival
// probabilities. Emission found by a BSDF ray counts pi * Le times its MIS weight; next-event samples of
// the same emitters carry the complementary weight (lights.cpp), so nothing is counted twice.
PathEstimate irradiance_path(const PathContext& c, const SamplePoint& point, Pcg32& rng) {
  const scene::Scene& scene = *c.scene;
  glm::vec3 result(0.0f), beta(1.0f), direct(0.0f);
  glm::vec3 x = point.position, n = point.normal;
  for (int bounce = 0; bounce < c.max_bounces; ++bounce) {
    result += beta * (punctual_irradiance(scene, *c.rays, x, n, c.epsilon) +
                      emitter_irradiance_sample(scene, *c.rays, *c.emitters, x, n, c.epsilon, rng));
    const float u1 = rng.uniform(), u2 = rng.uniform();
    if (bounce == 0) direct = result; // next-event light at the receiver itself
    const glm::vec3 w = cosine_hemisphere(n, u1, u2);
    const float cos_x = glm::dot(n, w);
    if (cos_x <= 0.0f) break;
    const auto hit = c.rays->intersect(x + c.epsilon * n, w);
    if (!hit) { // the sky: light the probes carry, so never `direct` (docs/LIGHTING.md "The sky")
      result += beta * (kPi * scene.sky.radiance(w));
      break;
    }
    if (hit->inside()) break; // the back of a single-sided surface (inside a solid): no light
    // Either side of a double-sided surface reflects and emits like a front side, about its facing normal.
    const glm::vec3 facing = hit->facing_normal();
    const glm::vec3 y = triangle_point(scene, hit->triangle, hit->u, hit->v);
    const glm::vec3 emission = scene.triangle_emission[hit->triangle];
    if (emission_weight(emission) > 0.0f) { // distance from x, as next-event estimation measures it
      const float cos_y = -glm::dot(facing, w);
      const glm::vec3 seen =
          beta * emission * (kPi * bsdf_hit_weight(*c.emitters, hit->triangle, cos_x, glm::length(y - x), cos_y));
      result += seen;
      if (bounce == 0) direct += seen; // an emitter the receiver's own ray sees
    }
    beta *= glm::clamp(scene.triangle_albedo[hit->triangle], 0.0f, 1.0f);
    if (bounce + 1 >= c.roulette_after) {
      const float survive = survival_probability(beta);
      if (!(survive > 0.0f) || rng.uniform() >= survive) break;
      beta /= survive;
    } else if (max_component(beta) <= 0.0f) {
      break;
    }
    x = y;
    n = facing;
  }
  return {result, direct};
}

} // namespace probebake::bake::detail
