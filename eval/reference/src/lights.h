// Direct lighting for the reference path tracer: punctual lights (exact, one shadow ray each) and
// next-event estimation on emissive triangles (area sampling proportional to emitted power, MIS-weighted
// against cosine-weighted BSDF sampling).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/scene/ray_scene.h"
#include "probebake/scene/scene.h"
#include "rng.h"

namespace probebake::bake::detail {

// Emissive triangles with a CDF over their power (area x mean emitted radiance).
class EmitterTable {
public:
  explicit EmitterTable(const scene::Scene& scene);

  bool empty() const { return triangles_.empty(); }
  // Density, per unit area, of the points that sample() returns on triangle t (0 when t is not sampled).
  float pdf_area(std::uint32_t t) const;
  // A triangle chosen proportionally to power, and a uniform point on it.
  struct Sample {
    std::uint32_t triangle = 0;
    glm::vec3 position{0.0f};
  };
  Sample sample(Pcg32& rng) const;

private:
  const scene::Scene* scene_;
  std::vector<std::uint32_t> triangles_;
  std::vector<double> cdf_;            // inclusive prefix sums of the power weights, normalised to 1
  std::vector<float> pdf_by_triangle_; // pdf_area per scene triangle (0 = not an emitter)
};

// Weight of triangle t in the emitter table: its emitted radiance averaged over the channels, >= 0.
float emission_weight(const glm::vec3& emission);

// Irradiance at surface point x with unit normal n from every punctual light, each with one shadow ray
// from x lifted by epsilon along n.
glm::vec3 punctual_irradiance(const scene::Scene& scene, const scene::RayScene& rays, const glm::vec3& x,
                              const glm::vec3& n, float epsilon);

// One light sample of the irradiance at x from emissive triangles, MIS-weighted against cosine sampling.
// Single-sided emitters light only their front; double-sided ones both sides (pdf with |cos| at the emitter).
glm::vec3 emitter_irradiance_sample(const scene::Scene& scene, const scene::RayScene& rays,
                                    const EmitterTable& emitters, const glm::vec3& x, const glm::vec3& n, float epsilon,
                                    Pcg32& rng);

// MIS weight of a cosine-sampled ray (density cos_x / pi) that hit emitter triangle t at distance dist
// with cosine cos_y at the emitter, measured against the normal of the side it hit (> 0 for any hit that
// counts: the front, or either side of a double-sided emitter).
float bsdf_hit_weight(const EmitterTable& emitters, std::uint32_t t, float cos_x, float dist, float cos_y);

} // namespace probebake::bake::detail
