#include "refine_sample.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "probebake/probe_index/lookup.h"
#include "probebake/common/lattice.h"

namespace probebake::placement {
namespace {

// Measured on the Cornell box (docs/results/placement.md, "Error-driven refinement and a probe budget
// (issue #13, first bullet)"): ranking leaves needs far fewer emitter patches and light rays than lighting
// probes does.
constexpr int kEstimateEmitterSamples = 8;
constexpr int kEstimateRays = 64;
constexpr float kPi = 3.14159265f;
constexpr float kMinCosine = 0.2f; // grazing hits: area per ray capped at 5x the facing one

lighting::LightingSettings estimate_settings(const RefineSettings& s) {
  lighting::LightingSettings l = s.lighting;
  l.emitter_samples = std::min(l.emitter_samples, kEstimateEmitterSamples);
  return l;
}

} // namespace

CandidateSampler::CandidateSampler(const PlacementInput& in, bool estimate)
    : in_(in),
      direct_(in.rays->scene(), *in.rays, estimate_settings(in.refine)),
      lighting_(estimate_settings(in.refine)),
      light_directions_(lattice_directions(Lattice::fibonacci, kEstimateRays)) {
  const scene::Scene& scene = in.rays->scene();
  const auto positive = [](glm::vec3 v) { return v.x > 0.0f || v.y > 0.0f || v.z > 0.0f; };
  estimate_ = estimate;
  lit_ = !scene.lights.empty() || scene.sky.emits() ||
         std::any_of(scene.triangle_emission.begin(), scene.triangle_emission.end(), positive);
}

CandidateSample CandidateSampler::sample(glm::vec3 position, const Cube& cube) const {
  CandidateSample out;
  std::vector<gpu::Surfel> surfels;
  out.rays = trace_probe(*in_.rays, position, cube, in_.directions, &surfels);
  const float solid_angle = 4.0f * kPi / float(in_.directions.size());
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    const gpu::Surfel& s = surfels[i];
    if ((s.flags & gpu::SURFEL_FLAG_HIT) == 0 || (s.flags & gpu::SURFEL_FLAG_BACKFACE) != 0) continue;
    const float cosine = std::max(std::abs(glm::dot(s.normal, in_.directions[i])), kMinCosine);
    out.visible_area += s.distance * s.distance * solid_angle / cosine;
  }
  if (!estimate_ || !lit_) return out;
  const scene::Scene& scene = in_.rays->scene();
  const float weight = 4.0f * kPi / float(light_directions_.size());
  for (const glm::vec3& d : light_directions_) {
    const auto hit = in_.rays->intersect(position, d);
    glm::vec3 radiance = scene.sky.radiance(d);
    if (hit && hit->inside())
      radiance = glm::vec3(0.0f);
    else if (hit) {
      const glm::vec3 n = hit->facing_normal();
      const glm::vec3 reflect = scene.triangle_albedo[hit->triangle] / kPi;
      const glm::vec3 emitted = lighting_.emissive_as_lights ? glm::vec3(0.0f) : scene.triangle_emission[hit->triangle];
      radiance = emitted + reflect * direct_.irradiance(position + hit->distance * d, n);
    }
    out.sh[0] += radiance * (weight * probe_index::kShBand0 * probe_index::kShY0);
    out.sh[1] += radiance * (weight * probe_index::kShBand1 * probe_index::kShY1 * d.y);
    out.sh[2] += radiance * (weight * probe_index::kShBand1 * probe_index::kShY1 * d.z);
    out.sh[3] += radiance * (weight * probe_index::kShBand1 * probe_index::kShY1 * d.x);
  }
  return out;
}

float sh_distance2(const std::array<glm::vec3, 4>& a, const std::array<glm::vec3, 4>& b) {
  float sum = 0.0f;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const glm::vec3 d = a[k] - b[k];
    sum += glm::dot(d, d);
  }
  return sum;
}

} // namespace probebake::placement
