// Probe placement: the adaptive octree of the octree thesis (§3.2.2 L1, run to convergence on the CPU)
// and the uniform grid baseline. Both fill a ProbeVolume through formats::Octree.
#pragma once

#include <optional>
#include <vector>

#include "probe_tracing.h"
#include "probebake/bake/bake.h"
#include "probebake/formats/octree.h"

namespace probebake::bake::detail {

struct PlacementInput {
  const scene::RayScene* rays = nullptr;
  const BakeSettings* settings = nullptr;
  std::vector<glm::vec3> directions; // the lattice
  float clearance = 0.0f;            // the bake's effective clearance (a centre nearer a surface is moved)
};

// A placed probe and the cube it must stay in (its octree node, or its grid cell).
struct PlacedProbe {
  int probe = 0;
  Cube cube;
  ProbeRays rays;
};

// Octree: starts from the root leaf; each leaf gets a probe at its centre whose hit fraction f decides:
// f < split_low frees the probe, f >= split_high below max_depth splits the node, otherwise it stays.
// Newly created children are evaluated in the next round until nothing changes.
std::vector<PlacedProbe> place_octree(const PlacementInput& in, formats::Octree& tree, const ProgressCallback& progress);

// Sealed triangles, which placement and lighting never see: every sample point just in front of the
// triangle (its centroid and three points near its corners) sees mostly back faces over its front
// hemisphere (is_dead's back-face rule), so it lies inside a solid and no point of open space can see
// it, e.g. a cube hidden inside a block. Without this, such triangles split octree nodes inside solids
// and move probes although nothing visible changed. A double-sided triangle is seen from both sides, so
// it is sealed only when the sample points in front of both sides are.
std::vector<char> sealed_triangles(const scene::RayScene& rays, int threads);
// `scene` without the sealed triangles (same vertices, materials, lights and bounds), or nothing when
// none is sealed.
std::optional<scene::Scene> without_sealed(const scene::Scene& scene, const std::vector<char>& sealed);

// Grid: N^3 probes at the cell centres of the scene bounds (node -1, depth 0).
std::vector<PlacedProbe> place_grid(const PlacementInput& in, formats::Octree& tree, const scene::Bounds& bounds);

} // namespace probebake::bake::detail
