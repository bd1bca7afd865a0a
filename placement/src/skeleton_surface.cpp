// Surface samples and the per-sample term of the skeleton objective (nonuniform-probe-placement-svo.txt
// §3.2: visibility, and the projected solid angle -w.n of the surface seen; our distance falloff, see
// skeleton.h).
#include "skeleton_internal.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "probebake/common/parallel.h"

namespace probebake::placement {
namespace {

std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

} // namespace

float hash_uniform(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  const std::uint64_t h = mix64(mix64(seed) ^ mix64(stream * 0x632be59bd9b4e019ull + index));
  return float(h >> 40) * 0x1.0p-24f;
}

std::vector<SurfaceSample> sample_surface(const scene::Scene& scene, int count, std::uint64_t seed) {
  const scene::ReceivingSides receiving = scene::receiving_sides(scene);
  const std::vector<scene::ReceivingSide>& sides = receiving.sides;
  const std::vector<double>& cdf = receiving.cumulative_area;
  const double total = receiving.total_area;
  std::vector<SurfaceSample> out;
  if (sides.empty() || count < 1) return out;
  out.reserve(std::size_t(count));
  for (int i = 0; i < count; ++i) {
    // Stratified along the cumulative area: sample i takes the side at (i + u) / count.
    const double u = (double(i) + double(hash_uniform(seed, 0, std::uint64_t(i)))) / double(count) * total;
    const std::size_t k =
        std::min(std::size_t(std::lower_bound(cdf.begin(), cdf.end(), u) - cdf.begin()), sides.size() - 1);
    const glm::uvec3 tri = scene.triangles[sides[k].triangle];
    const float r1 = std::sqrt(hash_uniform(seed, 1, std::uint64_t(i))), r2 = hash_uniform(seed, 2, std::uint64_t(i));
    const glm::vec3 p = (1.0f - r1) * scene.positions[tri.x] + r1 * (1.0f - r2) * scene.positions[tri.y] +
                        r1 * r2 * scene.positions[tri.z];
    const glm::vec3 n = scene::triangle_normal(scene, sides[k].triangle);
    out.push_back({p, sides[k].back ? -n : n});
  }
  return out;
}

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
