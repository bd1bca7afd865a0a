// Sealed triangles, which placement and lighting never see: every sample point just in front of the
// triangle (its centroid and three points near its corners) sees mostly back faces over its front
// hemisphere (is_dead's back-face rule), so it lies inside a solid and no point of open space can see
// it, e.g. a cube hidden inside a block. Without this, such triangles split octree nodes inside solids
// and move probes although nothing visible changed. A double-sided triangle is seen from both sides, so
// it is sealed only when the sample points in front of both sides are.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "probebake/scene/ray_scene.h"
#include "probebake/scene/scene.h"

namespace probebake::placement {

// 1 per sealed triangle of rays.scene(), else 0.
std::vector<char> sealed_triangles(const scene::RayScene& rays, int threads);
// The flags of the listed triangles only, in the list's order: each the value sealed_triangles gives it (a
// part of a split bake tests its cells' triangles).
std::vector<char> sealed_triangles(const scene::RayScene& rays, std::span<const std::uint32_t> triangles, int threads);
// `scene` without the sealed triangles (same vertices, materials, lights and bounds), or nothing when
// none is sealed.
std::optional<scene::Scene> without_sealed(const scene::Scene& scene, const std::vector<char>& sealed);

} // namespace probebake::placement
