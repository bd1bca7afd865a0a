// A voxel's sample points (voxel_samples.h).
#include "voxel_samples.h"

#include <glm/geometric.hpp>

namespace probebake::probe_index::detail {

bool inside_geometry(const scene::RayScene& rays, glm::vec3 p) {
  static const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  int back = 0;
  for (const glm::vec3& d : axes) {
    const auto hit = rays.intersect(p, d);
    back += hit && hit->inside() ? 1 : 0;
  }
  return back >= 4;
}

bool sees(const scene::RayScene& rays, glm::vec3 from, glm::vec3 to) {
  const glm::vec3 d = to - from;
  const float dist = glm::length(d);
  return dist == 0.0f || !rays.occluded(from, d / dist, 0.0f, dist);
}

Points voxel_points(glm::vec3 min, glm::vec3 extent) {
  Points p;
  p[0] = min + 0.5f * extent;
  for (int o = 0; o < 8; ++o)
    p[std::size_t(o) + 1] =
        min + extent * glm::vec3(o & 1 ? 0.75f : 0.25f, o & 2 ? 0.75f : 0.25f, o & 4 ? 0.75f : 0.25f);
  return p;
}

VoxelSamples sample_voxel(const scene::RayScene& rays, glm::vec3 min, glm::vec3 extent) {
  VoxelSamples s{voxel_points(min, extent), {}, false};
  for (std::size_t i = 0; i < s.points.size(); ++i) s.any_open |= (s.open[i] = !inside_geometry(rays, s.points[i]));
  return s;
}

} // namespace probebake::probe_index::detail
