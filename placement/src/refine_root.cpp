#include "probebake/placement/refine_root.h"

#include <algorithm>
#include <cstdint>

#include <glm/vector_relational.hpp>

#include "probebake/common/parallel.h"
#include "probebake/placement/probe_tracing.h"
#include "surface_samples.h" // points stratified by area, each with the normal of the side it is on

namespace probebake::placement {
namespace {

constexpr int kOpenProbeCells = 8; // 512 points: any room-scale open space holds several
constexpr float kSurroundScale = 3.0f;
constexpr int kSurfaceSamples = 512;      // points on the surfaces, spread by area: a room's floor and walls get many
constexpr std::uint64_t kSurfaceSeed = 1; // the same points every bake

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

bool inside(const scene::Bounds& bounds, glm::vec3 p) {
  return glm::all(glm::greaterThanEqual(p, bounds.min)) && glm::all(glm::lessThanEqual(p, bounds.max));
}

// Whether the point halfway between a surface sample and what its side sees along its normal (or the root
// cube's side) is open space inside the scene's bounds. A floor sees its ceiling, so the point lies at
// mid-height in the room, however flat the world and wherever the grids' points fall (on a table, in a wall).
// The bounds, not the root cube: the root of a closed object may have a margin around it (the skeleton's
// root_pad_clearances), and that margin is the outside the object is seen from.
bool open_in_front_of(const scene::RayScene& rays, const Cube& root, const scene::Bounds& bounds,
                      const SurfaceSample& sample, float clearance, const std::vector<glm::vec3>& directions) {
  float reach = root.exit_distance(sample.position, sample.normal);
  if (const auto hit = rays.intersect(sample.position, sample.normal, scene::ray_epsilon(rays.scene()), reach))
    reach = hit->distance;
  const glm::vec3 middle = sample.position + sample.normal * (0.5f * reach);
  return inside(bounds, middle) && is_open(rays, middle, clearance, directions);
}

bool open_point_in_front_of_surfaces(const scene::RayScene& rays, const gpu::VolumeInfo& info,
                                     const scene::Bounds& bounds, float clearance,
                                     const std::vector<glm::vec3>& directions, int threads) {
  const std::vector<SurfaceSample> samples = sample_surface(rays.scene(), kSurfaceSamples, kSurfaceSeed);
  const Cube root{info.root_min, info.root_size};
  std::vector<char> open(samples.size(), 0);
  parallel_for(open.size(), threads, [&](std::size_t i) {
    open[i] = open_in_front_of(rays, root, bounds, samples[i], clearance, directions) ? 1 : 0;
  });
  return std::find(open.begin(), open.end(), 1) != open.end();
}

} // namespace

bool open_space_inside(const scene::RayScene& rays, const gpu::VolumeInfo& info, const scene::Bounds& bounds,
                       float clearance, const std::vector<glm::vec3>& directions, int threads) {
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
