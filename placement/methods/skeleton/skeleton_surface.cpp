// The per-sample term of the skeleton objective (nonuniform-probe-placement-svo.txt §3.2: visibility, and
// the projected solid angle -w.n of the surface seen; our distance falloff, see skeleton.h). The samples
// themselves are placement/src/surface_samples.h's.
#include "skeleton_internal.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "probebake/common/parallel.h"

namespace probebake::placement {

float sample_quality(const scene::RayScene& rays, glm::vec3 probe, const SurfaceSample& s, float falloff) {
  const glm::vec3 v = probe - s.position;
  const float d2 = glm::dot(v, v);
  if (!(d2 > 0.0f)) return 0.0f;
  const float d = std::sqrt(d2);
  const glm::vec3 dir = v / d;
  const float cosine = glm::dot(s.normal, dir);
  if (!(cosine > 0.0f)) return 0.0f;
  const float eps = scene::ray_epsilon(rays.scene());
  if (d > 2.0f * eps && rays.occluded(s.position + eps * s.normal, dir, 0.0f, d - eps)) return 0.0f;
  const float l2 = falloff * falloff;
  return cosine * l2 / (l2 + d2);
}

void quality_row(const ObjectiveContext& ctx, glm::vec3 position, float* out) {
  const std::vector<SurfaceSample>& samples = *ctx.samples;
  parallel_for(samples.size(), ctx.threads,
               [&](std::size_t s) { out[s] = sample_quality(*ctx.rays, position, samples[s], ctx.falloff); });
}

QualityMatrix quality_matrix(const ObjectiveContext& ctx, const std::vector<glm::vec3>& positions) {
  QualityMatrix m;
  m.rows = positions.size();
  m.cols = ctx.samples->size();
  m.q.resize(m.rows * m.cols);
  // One task per (row, sample) pair: rows alone would leave a core idle on a small budget.
  parallel_for(m.q.size(), ctx.threads, [&](std::size_t i) {
    m.q[i] = sample_quality(*ctx.rays, positions[i / m.cols], (*ctx.samples)[i % m.cols], ctx.falloff);
  });
  return m;
}

float coverage(const scene::RayScene& rays, const std::vector<glm::vec3>& probes,
               const std::vector<glm::vec3>& reference, const std::vector<SurfaceSample>& samples, int threads) {
  std::vector<char> seen(samples.size(), 0), reachable(samples.size(), 0);
  parallel_for(samples.size(), threads, [&](std::size_t s) {
    const auto sees = [&](glm::vec3 p) { return sample_quality(rays, p, samples[s], 1.0f) > 0.0f; };
    reachable[s] = std::any_of(reference.begin(), reference.end(), sees) ? 1 : 0;
    seen[s] = reachable[s] != 0 && std::any_of(probes.begin(), probes.end(), sees) ? 1 : 0;
  });
  const auto n = std::count(reachable.begin(), reachable.end(), 1);
  return n > 0 ? float(std::count(seen.begin(), seen.end(), 1)) / float(n) : 0.0f;
}

} // namespace probebake::placement
