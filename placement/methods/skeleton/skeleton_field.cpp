// The skeleton's distance grid, its ridge voxels (the discrete medial axis) and the Poisson-disc
// candidates taken from them (nonuniform-probe-placement-svo.txt §3.1, "Signed Distance Function
// Skeletonization").
#include "skeleton_internal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <glm/common.hpp>

#include "probebake/common/parallel.h"

namespace probebake::placement {

glm::ivec3 DistanceGrid::voxel_of(std::size_t i) const {
  const std::size_t nx = std::size_t(dims.x), ny = std::size_t(dims.y);
  return {int(i % nx), int((i / nx) % ny), int(i / (nx * ny))};
}

DistanceGrid sample_distance(const SceneSdf& sdf, const scene::Bounds& domain, float voxel, int threads) {
  DistanceGrid grid;
  grid.voxel = voxel;
  const glm::vec3 extent = domain.max - domain.min;
  grid.dims = glm::max(glm::ivec3(glm::floor(extent / voxel)), glm::ivec3(1));
  // Centred in the domain: the leftover of the floor splits evenly on both sides.
  const glm::vec3 span = glm::vec3(grid.dims - 1) * voxel;
  grid.origin = domain.min + 0.5f * (extent - span);
  grid.distance.resize(std::size_t(grid.dims.x) * std::size_t(grid.dims.y) * std::size_t(grid.dims.z));
  parallel_for(grid.distance.size(), threads,
               [&](std::size_t i) { grid.distance[i] = sdf.distance(grid.centre(grid.voxel_of(i))); });
  return grid;
}

namespace {

// Half of the 26-neighbourhood: one of each opposite pair.
constexpr std::array<glm::ivec3, 13> kAxes = {{{1, 0, 0},
                                               {0, 1, 0},
                                               {0, 0, 1},
                                               {1, 1, 0},
                                               {1, -1, 0},
                                               {1, 0, 1},
                                               {1, 0, -1},
                                               {0, 1, 1},
                                               {0, 1, -1},
                                               {1, 1, 1},
                                               {1, 1, -1},
                                               {1, -1, 1},
                                               {1, -1, -1}}};

bool inside(const DistanceGrid& g, glm::ivec3 v) {
  return v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < g.dims.x && v.y < g.dims.y && v.z < g.dims.z;
}

// Along `axis`, at least as deep as both neighbours (up to the field's noise) and half a voxel deeper than
// the shallower one. The strict margin matters: next to a flat wall the distance is constant along the
// wall's axes up to the SDF's discretisation error (~5 % of a voxel measured), a noisy plateau that an
// exact comparison takes for ridges. A true ridge falls by about a voxel on its shallow side along some
// axis. Both neighbours must be in the grid.
bool ridge_along(const DistanceGrid& g, glm::ivec3 v, glm::ivec3 axis, float d) {
  const glm::ivec3 a = v + axis, b = v - axis;
  if (!inside(g, a) || !inside(g, b)) return false;
  const float da = g.distance[g.index(a)], db = g.distance[g.index(b)];
  const float noise = 0.1f * g.voxel;
  return d + noise >= std::max(da, db) && d - std::min(da, db) >= 0.5f * g.voxel;
}

} // namespace

std::vector<std::size_t> skeleton_voxels(const DistanceGrid& grid, float clearance) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < grid.distance.size(); ++i) {
    const float d = grid.distance[i];
    if (!(d >= clearance)) continue;
    const glm::ivec3 v = grid.voxel_of(i);
    if (std::any_of(kAxes.begin(), kAxes.end(), [&](glm::ivec3 axis) { return ridge_along(grid, v, axis, d); }))
      out.push_back(i);
  }
  return out;
}

namespace {

// Greedy Poisson disc: voxels in order, each kept unless a kept one lies within `radius` (hash grid of
// cells `radius` wide, 27 cells searched).
std::vector<std::size_t> poisson_subset(const DistanceGrid& grid, const std::vector<std::size_t>& order, float radius) {
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells;
  const auto key = [](glm::ivec3 c) {
    return (std::uint64_t(std::uint32_t(c.x) & 0x1fffff) << 42) | (std::uint64_t(std::uint32_t(c.y) & 0x1fffff) << 21) |
           std::uint64_t(std::uint32_t(c.z) & 0x1fffff);
  };
  std::vector<std::size_t> kept;
  for (std::size_t i : order) {
    const glm::vec3 p = grid.centre(grid.voxel_of(i));
    const glm::ivec3 c = glm::ivec3(glm::floor(p / radius));
    bool near = false;
    for (int dz = -1; dz <= 1 && !near; ++dz)
      for (int dy = -1; dy <= 1 && !near; ++dy)
        for (int dx = -1; dx <= 1 && !near; ++dx) {
          const auto it = cells.find(key(c + glm::ivec3(dx, dy, dz)));
          if (it == cells.end()) continue;
          for (std::size_t j : it->second) {
            const glm::vec3 q = grid.centre(grid.voxel_of(j));
            if (glm::dot(p - q, p - q) < radius * radius) near = true;
          }
        }
    if (near) continue;
    kept.push_back(i);
    cells[key(c)].push_back(i);
  }
  return kept;
}

} // namespace

std::vector<glm::vec3> skeleton_candidates(const DistanceGrid& grid, const std::vector<std::size_t>& skeleton,
                                           float clearance, int max_candidates) {
  std::vector<std::size_t> order = skeleton;
  if (order.empty()) // no ridge (e.g. a single plane): every free voxel is a candidate
    for (std::size_t i = 0; i < grid.distance.size(); ++i)
      if (grid.distance[i] >= clearance) order.push_back(i);
  // Deepest first, index on ties: the centres of rooms before the sheets running into their corners.
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return grid.distance[a] > grid.distance[b]; });
  float radius = 0.99f * grid.voxel; // keeps every voxel
  std::vector<std::size_t> kept = poisson_subset(grid, order, radius);
  while (int(kept.size()) > max_candidates) {
    radius *= 1.25f;
    kept = poisson_subset(grid, order, radius);
  }
  std::vector<glm::vec3> out;
  out.reserve(kept.size());
  for (std::size_t i : kept) out.push_back(grid.centre(grid.voxel_of(i)));
  return out;
}

} // namespace probebake::placement
