// Area-uniform surface samples (surface_samples.h), moved here from the skeleton method's files because the
// root cube's test (refine_root.cpp) samples the surfaces too.
#include "surface_samples.h"

#include <algorithm>
#include <cmath>

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

} // namespace probebake::placement
