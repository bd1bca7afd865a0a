#include "probebake/placement/refine_root.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "probebake/common/parallel.h"
#include "probebake/placement/probe_tracing.h"

namespace probebake::placement {
namespace {

constexpr int kOpenProbeCells = 8;    // 512 points: any room-scale open space holds several
constexpr float kSurroundScale = 3.0f;
constexpr int kSurfaceSamples = 512;  // points on the surfaces, spread by area: a room's floor and walls get many

// Whether any centre of a kOpenProbeCells^3 grid over the box is open space.
bool open_point_in_grid(const scene::RayScene& rays, glm::vec3 min, glm::vec3 size, float clearance,
                        const std::vector<glm::vec3>& directions, int threads) {
  const int n = kOpenProbeCells;
  const glm::vec3 cell = size / float(n);
  std::vector<char> open(std::size_t(n * n * n), 0);
  parallel_for(open.size(), threads, [&](std::size_t i) {
    const glm::vec3 index(float(int(i) % n), float(int(i) / n % n), float(int(i) / (n * n)));
    open[i] = is_open(rays, min + (index + 0.5f) * cell, clearance, directions) ? 1 : 0;
  });
  return std::find(open.begin(), open.end(), 1) != open.end();
}

// Point `sample` of kSurfaceSamples on the surfaces: the triangles are stratified by area, and within its
// triangle the sample takes the rest of its stratum and a golden-ratio sequence as coordinates.
struct SurfacePoint {
  std::size_t triangle = 0;
  glm::vec3 position{0.0f};
};

SurfacePoint surface_point(const scene::Scene& s, const std::vector<double>& area_below, int sample) {
  const double total = area_below.back();
  const double target = (double(sample) + 0.5) / kSurfaceSamples * total;
  const auto above = std::upper_bound(area_below.begin(), area_below.end(), target);
  const std::size_t t = std::min<std::size_t>(std::size_t(above - area_below.begin()), s.triangles.size()) - 1;
  const double share = area_below[t + 1] - area_below[t];
  const float r1 = share > 0.0 ? float(std::clamp((target - area_below[t]) / share, 0.0, 1.0)) : 0.5f;
  const float r2 = float(std::fmod(0.6180339887498949 * double(sample + 1), 1.0));
  const float su = std::sqrt(r1);
  const glm::uvec3 tri = s.triangles[t];
  return {t, (1.0f - su) * s.positions[tri.x] + su * (1.0f - r2) * s.positions[tri.y] + su * r2 * s.positions[tri.z]};
}

bool inside(const scene::Bounds& bounds, glm::vec3 p) {
  return glm::all(glm::greaterThanEqual(p, bounds.min)) && glm::all(glm::lessThanEqual(p, bounds.max));
}

// Whether the point halfway between a surface point and what its face sees along the normal (or the root
// cube's side) is open space inside the scene's bounds. A floor sees its ceiling, so the point lies at
// mid-height in the room, however flat the world and wherever the grids' points fall (on a table, in a wall).
// The bounds, not the root cube: the root of a closed object may have a margin around it (the skeleton's
// root_pad_clearances), and that margin is the outside the object is seen from.
bool open_in_front_of(const scene::RayScene& rays, const Cube& root, const scene::Bounds& bounds, const SurfacePoint& point,
                      float clearance, const std::vector<glm::vec3>& directions) {
  const scene::Scene& s = rays.scene();
  const glm::uvec3 tri = s.triangles[point.triangle];
  const glm::vec3 normal = glm::normalize(glm::cross(s.positions[tri.y] - s.positions[tri.x], s.positions[tri.z] - s.positions[tri.x]));
  const bool double_sided = s.materials[s.triangle_material[point.triangle]].double_sided;
  const float lift = 1e-4f * root.size; // off the surface it starts on
  for (const float side : {1.0f, -1.0f}) {
    if (side < 0.0f && !double_sided) break;
    const glm::vec3 d = side * normal;
    float reach = root.exit_distance(point.position, d);
    if (const auto hit = rays.intersect(point.position, d, lift, reach)) reach = hit->distance;
    const glm::vec3 middle = point.position + d * (0.5f * reach);
    if (inside(bounds, middle) && is_open(rays, middle, clearance, directions)) return true;
  }
  return false;
}

bool open_point_in_front_of_surfaces(const scene::RayScene& rays, const gpu::VolumeInfo& info, const scene::Bounds& bounds,
                                     float clearance, const std::vector<glm::vec3>& directions, int threads) {
  const scene::Scene& s = rays.scene();
  std::vector<double> area_below(s.triangles.size() + 1, 0.0); // prefix sums: area_below[t] = area of triangles < t
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const glm::uvec3 tri = s.triangles[t];
    const double area = 0.5 * double(glm::length(glm::cross(s.positions[tri.y] - s.positions[tri.x], s.positions[tri.z] - s.positions[tri.x])));
    area_below[t + 1] = area_below[t] + (std::isfinite(area) ? area : 0.0);
  }
  if (!(area_below.back() > 0.0)) return false;
  const Cube root{info.root_min, info.root_size};
  std::vector<char> open(kSurfaceSamples, 0);
  parallel_for(open.size(), threads, [&](std::size_t i) {
    const SurfacePoint point = surface_point(s, area_below, int(i));
    open[i] = open_in_front_of(rays, root, bounds, point, clearance, directions) ? 1 : 0;
  });
  return std::find(open.begin(), open.end(), 1) != open.end();
}

} // namespace

bool open_space_inside(const scene::RayScene& rays, const gpu::VolumeInfo& info, const scene::Bounds& bounds, float clearance,
                       const std::vector<glm::vec3>& directions, int threads) {
  if (open_point_in_grid(rays, info.root_min, glm::vec3(info.root_size), clearance, directions, threads)) return true;
  if (bounds.empty()) return false;
  if (open_point_in_grid(rays, bounds.min, bounds.max - bounds.min, clearance, directions, threads)) return true;
  return open_point_in_front_of_surfaces(rays, info, bounds, clearance, directions, threads);
}

void surround_root(gpu::VolumeInfo& info) {
  const glm::vec3 centre = info.root_min + glm::vec3(0.5f * info.root_size);
  info.root_size *= kSurroundScale;
  info.root_min = centre - glm::vec3(0.5f * info.root_size);
}

} // namespace probebake::placement
