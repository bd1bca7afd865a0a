#include "probebake/placement/refine_root.h"

#include <algorithm>

#include "probebake/common/parallel.h"
#include "probebake/placement/probe_tracing.h"

namespace probebake::placement {
namespace {

constexpr int kOpenProbeCells = 8;    // 512 points: any room-scale open space holds several
constexpr float kSurroundScale = 3.0f;

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

} // namespace

bool open_space_inside(const scene::RayScene& rays, const gpu::VolumeInfo& info, const scene::Bounds& bounds, float clearance,
                       const std::vector<glm::vec3>& directions, int threads) {
  if (open_point_in_grid(rays, info.root_min, glm::vec3(info.root_size), clearance, directions, threads)) return true;
  return !bounds.empty() && open_point_in_grid(rays, bounds.min, bounds.max - bounds.min, clearance, directions, threads);
}

void surround_root(gpu::VolumeInfo& info) {
  const glm::vec3 centre = info.root_min + glm::vec3(0.5f * info.root_size);
  info.root_size *= kSurroundScale;
  info.root_min = centre - glm::vec3(0.5f * info.root_size);
}

} // namespace probebake::placement
