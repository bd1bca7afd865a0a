#include "probebake/placement/probe_tracing.h"

#include <algorithm>
#include <cmath>

namespace probebake::placement {

bool Cube::contains(glm::vec3 p) const {
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= min[a] && p[a] <= min[a] + size)) return false;
  return true;
}

float Cube::exit_distance(glm::vec3 inside, glm::vec3 direction) const {
  float t = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (direction[a] > 0.0f)
      t = std::min(t, (min[a] + size - inside[a]) / direction[a]);
    else if (direction[a] < 0.0f)
      t = std::min(t, (min[a] - inside[a]) / direction[a]);
  }
  return std::max(t, 0.0f);
}

ProbeRays trace_probe(const scene::RayScene& rays, glm::vec3 position, const Cube& cube,
                      std::span<const glm::vec3> directions, std::vector<gpu::Surfel>* surfels) {
  ProbeRays r;
  r.rays = int(directions.size());
  if (surfels != nullptr) surfels->assign(directions.size(), gpu::Surfel{});
  const scene::Scene& scene = rays.scene();
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const glm::vec3 d = directions[i];
    const float exit = cube.exit_distance(position, d);
    const auto hit = rays.intersect(position, d);
    const bool in_cube = hit.has_value() && hit->distance <= exit;
    if (hit) {
      ++r.hits;
      r.backface_hits += hit->inside() ? 1 : 0;
      r.hits_in_cube += in_cube ? 1 : 0;
      if (hit->distance < r.nearest) {
        r.nearest = hit->distance;
        r.nearest_point = position + d * hit->distance;
        r.nearest_normal = hit->normal;
        r.nearest_backface = hit->inside();
        r.nearest_facing_normal = hit->facing_normal();
        r.nearest_double_sided = hit->double_sided;
      }
    }
    if (surfels == nullptr) continue;
    gpu::Surfel& s = (*surfels)[i];
    s.distance = in_cube ? hit->distance : exit;
    s.position = position + d * s.distance;
    if (in_cube) {
      // The back of a double-sided surface is a lit surface facing the probe, not the inside of a solid.
      s.flags = gpu::SURFEL_FLAG_HIT | (hit->inside() ? gpu::SURFEL_FLAG_BACKFACE : 0u);
      s.normal = hit->facing_normal(); // the side facing the probe
      s.albedo = scene.triangle_albedo[hit->triangle];
    }
  }
  return r;
}

bool is_dead(const ProbeRays& r, float clearance) { return r.backface_fraction() > 0.5f || r.nearest < clearance; }

bool mostly_back_faces(const scene::RayScene& rays, glm::vec3 p, std::span<const glm::vec3> directions) {
  // 2 * back - hits decides (> 0: dead); each ray left moves it by at most one either way.
  int margin = 0;
  int left = int(directions.size());
  for (const glm::vec3& d : directions) {
    --left;
    if (const auto hit = rays.intersect(p, d)) margin += hit->inside() ? 1 : -1;
    if (margin - left > 0) return true;
    if (margin + left <= 0) return false;
  }
  return margin > 0;
}

float default_clearance(const scene::Scene& scene) { return 0.02f * std::max(scene.bounds.largest_extent(), 1e-6f); }

bool is_open(const scene::RayScene& rays, glm::vec3 p, float clearance, std::span<const glm::vec3> directions) {
  return !is_dead(trace_probe(rays, p, Cube{p, 0.0f}, directions), clearance);
}

} // namespace probebake::placement
