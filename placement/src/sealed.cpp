// Sealed triangles: inside solids, unseen from open space (sealed.h says why placement ignores them).
#include "probebake/placement/sealed.h"

#include <algorithm>
#include <array>
#include <numeric>

#include <glm/geometric.hpp>

#include "probebake/common/lattice.h"
#include "probebake/common/parallel.h"
#include "probebake/placement/probe_tracing.h"

namespace probebake::placement {
namespace {

constexpr int kSealRays = 64;        // per sample point, over the front hemisphere
constexpr int kSealScreenStride = 8; // 8 of the 64 directions screen first

// Fibonacci directions flipped into the hemisphere around `n` (the sphere lattice is symmetric enough).
glm::vec3 into_front(glm::vec3 d, glm::vec3 n) { return glm::dot(d, n) < 0.0f ? -d : d; }

// Sealed on the side `n` faces: every sample point lifted off that side sees mostly back faces of
// single-sided surfaces (trace_probe counts only RayHit::inside() hits).
bool side_sealed(const scene::RayScene& rays, std::uint32_t t, glm::vec3 n, const std::vector<glm::vec3>& sphere,
                 float lift) {
  const scene::Scene& s = rays.scene();
  const glm::uvec3 tri = s.triangles[t];
  const glm::vec3 a = s.positions[tri.x], b = s.positions[tri.y], c = s.positions[tri.z];
  const glm::vec3 samples[] = {(a + b + c) / 3.0f, 0.8f * a + 0.1f * (b + c), 0.8f * b + 0.1f * (a + c),
                               0.8f * c + 0.1f * (a + b)};
  // Screen: most triangles are plainly visible. Every kSealScreenStride-th lattice direction (spread over
  // the hemisphere) from the centroid; if none of them meets a back face, the triangle is open without
  // the full test (which cost ten times the rest of the bvh stage on a 291k-triangle scene).
  // (No allocation on this path, which every triangle takes.)
  std::array<glm::vec3, kSealRays / kSealScreenStride> screen;
  for (std::size_t i = 0; i < screen.size(); ++i) screen[i] = into_front(sphere[i * kSealScreenStride], n);
  const glm::vec3 centroid = samples[0] + lift * n;
  if (trace_probe(rays, centroid, Cube{centroid, 0.0f}, screen).backface_hits == 0) return false;
  std::vector<glm::vec3> dirs(sphere.size());
  std::transform(sphere.begin(), sphere.end(), dirs.begin(), [&](glm::vec3 d) { return into_front(d, n); });
  for (const glm::vec3& p : samples)
    if (!mostly_back_faces(rays, p + lift * n, dirs)) return false; // is_open at clearance 0
  return true;
}

// A single-sided triangle is seen only from its front; a double-sided one from both sides, so it is
// sealed only when both are (a double-sided plane inside a solid, not a double-sided wall of a room).
bool triangle_sealed(const scene::RayScene& rays, std::uint32_t t, const std::vector<glm::vec3>& sphere, float lift) {
  const scene::Scene& s = rays.scene();
  const glm::vec3 n = scene::triangle_normal(s, t);
  if (n == glm::vec3(0.0f)) return false; // degenerate: nothing to see either way
  if (!side_sealed(rays, t, n, sphere, lift)) return false;
  return !scene::is_double_sided(s, t) || side_sealed(rays, t, -n, sphere, lift);
}

} // namespace

std::vector<char> sealed_triangles(const scene::RayScene& rays, int threads) {
  std::vector<std::uint32_t> all(rays.scene().triangles.size());
  std::iota(all.begin(), all.end(), 0u);
  return sealed_triangles(rays, all, threads);
}

std::vector<char> sealed_triangles(const scene::RayScene& rays, std::span<const std::uint32_t> triangles, int threads) {
  const std::vector<glm::vec3> sphere = lattice_directions(Lattice::fibonacci, kSealRays);
  const float lift = scene::ray_epsilon(rays.scene()); // off the surface as the reference's rays are
  std::vector<char> sealed(triangles.size(), 0);
  parallel_for(sealed.size(), threads,
               [&](std::size_t k) { sealed[k] = triangle_sealed(rays, triangles[k], sphere, lift) ? 1 : 0; });
  return sealed;
}

std::optional<scene::Scene> without_sealed(const scene::Scene& scene, const std::vector<char>& sealed) {
  if (std::find(sealed.begin(), sealed.end(), 1) == sealed.end()) return std::nullopt;
  scene::Scene out;
  out.positions = scene.positions;
  out.materials = scene.materials;
  out.lights = scene.lights; // what lights it: its lights and its sky
  out.sky = scene.sky;
  out.sun_light = scene.sun_light;
  out.bounds = scene.bounds; // the root cube and the clearance stay those of the whole scene
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    if (sealed[t] != 0) continue;
    out.triangles.push_back(scene.triangles[t]);
    out.triangle_material.push_back(scene.triangle_material[t]);
    out.triangle_albedo.push_back(scene.triangle_albedo[t]);
    out.triangle_emission.push_back(scene.triangle_emission[t]);
  }
  return out;
}

} // namespace probebake::placement
