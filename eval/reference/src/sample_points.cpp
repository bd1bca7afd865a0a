// surface_sample_points: area-stratified points on the sides of surfaces (front faces; both sides of
// double-sided ones), without points hidden inside geometry.
#include <algorithm>
#include <cmath>

#include <fmt/core.h>
#include <glm/geometric.hpp>

#include "probebake/common/parallel.h"
#include "probebake/eval/reference.h"
#include "probebake/formats/error.h"
#include "rng.h"
#include "sampling.h"

namespace probebake::bake {
namespace {

constexpr int kVisibilityRays = 32;
constexpr int kMaxRounds = 64;

// Fibonacci directions over the +Z hemisphere, uniform in solid angle.
const std::vector<glm::vec3>& hemisphere_directions() {
  static const std::vector<glm::vec3> dirs = [] {
    std::vector<glm::vec3> d;
    const float golden = detail::kPi * (3.0f - std::sqrt(5.0f));
    for (int i = 0; i < kVisibilityRays; ++i) {
      const float z = 1.0f - (float(i) + 0.5f) / float(kVisibilityRays);
      const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
      const float phi = golden * float(i);
      d.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
    return d;
  }();
  return dirs;
}

// Hidden: most of the hits over the hemisphere of the lifted point are inside solids (backs of single-sided
// surfaces: the point lies inside a closed object, e.g. the floor under a block).
bool hidden(const scene::RayScene& rays, const SamplePoint& p, float epsilon) {
  glm::vec3 t, b;
  detail::orthonormal_basis(p.normal, t, b);
  const glm::vec3 origin = p.position + epsilon * p.normal;
  int hits = 0, back = 0;
  for (const glm::vec3& d : hemisphere_directions()) {
    if (const auto hit = rays.intersect(origin, t * d.x + b * d.y + p.normal * d.z)) {
      ++hits;
      back += hit->inside() ? 1 : 0;
    }
  }
  return 2 * back > hits;
}

// A double-sided triangle is two surfaces of the same area, each a receiver (scene::receiving_sides).
struct AreaTable {
  std::vector<scene::ReceivingSide> sides;
  std::vector<double> cdf; // normalised inclusive prefix sums of the areas
};

AreaTable area_table(const scene::Scene& scene) {
  scene::ReceivingSides receiving = scene::receiving_sides(scene);
  AreaTable table{std::move(receiving.sides), std::move(receiving.cumulative_area)};
  for (double& c : table.cdf) c /= receiving.total_area;
  if (!table.cdf.empty()) table.cdf.back() = 1.0;
  return table;
}

struct Candidate {
  double u = 0.0; // position along the cumulative area, in [0, 1)
  SamplePoint point;
};

// One round of `count` candidates: candidate i takes the triangle at cumulative area (i + u) / count.
std::vector<Candidate> candidates(const scene::Scene& scene, const AreaTable& table, int count, std::uint64_t seed,
                                  int round) {
  detail::Pcg32 rng(seed, 0x5a3b1e0000000000ull + std::uint64_t(round));
  std::vector<Candidate> points;
  points.reserve(std::size_t(count));
  for (int i = 0; i < count; ++i) {
    const double u = (double(i) + double(rng.uniform())) / double(count);
    const auto it = std::lower_bound(table.cdf.begin(), table.cdf.end(), u);
    const scene::ReceivingSide side =
        table.sides[std::min(std::size_t(it - table.cdf.begin()), table.sides.size() - 1)];
    const glm::uvec3 tri = scene.triangles[side.triangle];
    const glm::vec3 front = scene::triangle_normal(scene, side.triangle);
    const float u1 = rng.uniform(), u2 = rng.uniform();
    points.push_back({u,
                      {detail::uniform_triangle_point(scene.positions[tri.x], scene.positions[tri.y],
                                                      scene.positions[tri.z], u1, u2),
                       side.back ? -front : front}});
  }
  return points;
}

} // namespace

std::vector<SamplePoint> surface_sample_points(const scene::Scene& scene, const scene::RayScene& rays, int count,
                                               std::uint64_t seed) {
  if (count < 1) throw Error(ErrorKind::usage, fmt::format("--points must be at least 1 (got {})", count));
  const AreaTable table = area_table(scene);
  if (table.sides.empty()) return {};
  const float epsilon = scene::ray_epsilon(scene);
  // Whole rounds of stratified candidates until enough are visible (each round is uniform over the visible
  // area, so their union is too); then `count` of them at even steps along the cumulative area.
  std::vector<Candidate> visible;
  for (int round = 0; round < kMaxRounds && int(visible.size()) < count; ++round) {
    const std::vector<Candidate> c = candidates(scene, table, count, seed, round);
    std::vector<char> keep(c.size(), 0);
    parallel_for(c.size(), 0, [&](std::size_t i) { keep[i] = hidden(rays, c[i].point, epsilon) ? 0 : 1; });
    for (std::size_t i = 0; i < c.size(); ++i)
      if (keep[i] != 0) visible.push_back(c[i]);
  }
  std::stable_sort(visible.begin(), visible.end(), [](const Candidate& a, const Candidate& b) { return a.u < b.u; });
  const std::size_t n = std::min(visible.size(), std::size_t(count));
  std::vector<SamplePoint> accepted;
  accepted.reserve(n);
  for (std::size_t j = 0; j < n; ++j) accepted.push_back(visible[(2 * j + 1) * visible.size() / (2 * n)].point);
  return accepted;
}

std::vector<SamplePoint> surface_sample_points(const scene::Scene& scene, int count, std::uint64_t seed) {
  const scene::RayScene rays(scene);
  return surface_sample_points(scene, rays, count, seed);
}

} // namespace probebake::bake
