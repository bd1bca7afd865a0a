// Tracing a probe's lattice: the measurements that drive placement (hit fraction inside the node cube,
// octree thesis §3.2.2 L1) and dead-probe detection (back-face fraction, DDGI relocation paper §3.1).
// "Back face" here always means RayHit::inside(): the back of a single-sided surface. The back of a
// glTF doubleSided surface is open space like its front (a probe that sees it is not inside anything).
#pragma once

#include <limits>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/scene/ray_scene.h"
#include "probebake/gpu_types.h"

namespace probebake::placement {

struct Cube {
  glm::vec3 min{0.0f};
  float size = 0.0f;
  glm::vec3 centre() const { return min + glm::vec3(0.5f * size); }
  bool contains(glm::vec3 p) const; // boundary included
  // Distance from `inside` along unit `direction` to the cube's boundary.
  float exit_distance(glm::vec3 inside, glm::vec3 direction) const;
};

struct ProbeRays {
  int rays = 0;
  int hits_in_cube = 0;  // hits no farther than the cube boundary
  int hits = 0;          // hits at any distance
  int backface_hits = 0; // of `hits`: hits that are inside() (backs of single-sided surfaces)
  float nearest = std::numeric_limits<float>::infinity(); // distance to the nearest hit
  glm::vec3 nearest_point{0.0f};
  glm::vec3 nearest_normal{0.0f}; // front-face (CCW) normal of the nearest hit
  bool nearest_backface = false;  // the nearest hit is inside() (behind a single-sided surface)
  // The nearest hit's side facing the probe (RayHit::facing_normal); meaningful when !nearest_backface.
  glm::vec3 nearest_facing_normal{0.0f};
  bool nearest_double_sided = false;

  float hit_fraction() const { return rays > 0 ? float(hits_in_cube) / float(rays) : 0.0f; }
  float backface_fraction() const { return hits > 0 ? float(backface_hits) / float(hits) : 0.0f; }
};

// Traces one ray per direction from `position`. When `surfels` is given, it receives one surfel per
// direction (hits inside the cube flagged SURFEL_FLAG_HIT; misses end at the cube boundary). A hit
// surfel's normal is the side facing the probe (facing_normal); it is flagged SURFEL_FLAG_BACKFACE only
// when the hit is inside() (the back of a single-sided surface), never on a double-sided surface.
ProbeRays trace_probe(const scene::RayScene& rays, glm::vec3 position, const Cube& cube,
                      std::span<const glm::vec3> directions, std::vector<gpu::Surfel>* surfels = nullptr);

// A probe is dead when most of its rays hit back faces of single-sided surfaces (it is inside geometry)
// or a surface (of either kind, seen from either side) is closer than the clearance.
bool is_dead(const ProbeRays& r, float clearance);

// is_dead's back-face rule alone (more than half of the hits are inside() hits) over `directions` from
// `p`, with the verdict of the full trace but stopping as soon as the remaining rays cannot change it.
bool mostly_back_faces(const scene::RayScene& rays, glm::vec3 p, std::span<const glm::vec3> directions);

// The clearance a bake uses when BakeSettings::clearance is 0: 2% of the scene's largest extent.
float default_clearance(const scene::Scene& scene);

// Open space: a probe at `p` would not be dead (is_dead) at `clearance` over `directions`. The eval's
// viewpoints use the bake's own test, so "where a player can be" and "where a probe can live" agree.
bool is_open(const scene::RayScene& rays, glm::vec3 p, float clearance, std::span<const glm::vec3> directions);

} // namespace probebake::placement
