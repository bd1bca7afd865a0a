// Dead-probe relocation, after the DDGI probe relocation paper (§3.1 detection by back-face hits, §3.2
// moving probes out of geometry). Where the paper nudges probes over many frames, the bake searches
// directly: the SDF gradient and the nearest surface's normal give geometry-aware candidates, and the
// paper's spiral search is the fallback. Every candidate is judged by is_dead over the full lattice, but
// the verdict is reached as early as it is certain: most candidates of a probe inside a wall fail within
// a few short rays instead of a full lattice each (the 64-room scene spent 23 s relocating).
#include "probebake/placement/relocation.h"

#include <cmath>

#include "probebake/common/lattice.h"
#include "probebake/placement/scene_sdf.h"

namespace probebake::placement {
namespace {

constexpr int kSpiralShells = 8;
constexpr int kSpiralPointsPerShell = 32;

// is_dead's clearance rule on its own: some lattice ray meets a surface nearer than the clearance. Short
// occlusion rays (tfar just below the clearance, as is_dead's `nearest < clearance`), first hit ends it.
bool surface_within_clearance(const RelocationContext& ctx, glm::vec3 p) {
  if (!(ctx.clearance > 0.0f)) return false;
  const float reach = std::nextafter(ctx.clearance, 0.0f);
  for (const glm::vec3& d : ctx.directions)
    if (ctx.rays->occluded(p, d, 0.0f, reach)) return true;
  return false;
}

} // namespace

bool is_valid_position(const RelocationContext& ctx, glm::vec3 p, const Cube& cube) {
  if (!cube.contains(p)) return false;
  return !surface_within_clearance(ctx, p) && !mostly_back_faces(*ctx.rays, p, ctx.directions);
}

std::optional<glm::vec3> relocate_probe(const RelocationContext& ctx, glm::vec3 position, const ProbeRays& rays,
                                        const Cube& cube) {
  if (ctx.sdf != nullptr) {
    if (auto out = ctx.sdf->push_out(position, ctx.clearance * 1.5f); out && is_valid_position(ctx, *out, cube))
      return out;
  }
  if (rays.hits > 0) {
    // Behind the nearest surface (a single-sided one seen from its back): cross it along its front
    // normal. In front of it, or of either side of a double-sided one, but too close: step back along
    // the normal of the side the probe sees.
    const glm::vec3 candidate = rays.nearest_backface
                                    ? rays.nearest_point + rays.nearest_normal * (ctx.clearance * 1.5f)
                                    : position + rays.nearest_facing_normal * (ctx.clearance * 1.5f - rays.nearest);
    if (is_valid_position(ctx, candidate, cube)) return candidate;
  }
  const float max_radius = 0.5f * cube.size * std::sqrt(3.0f);
  for (int shell = 1; shell <= kSpiralShells; ++shell) {
    const float radius = max_radius * float(shell) / float(kSpiralShells);
    for (int i = 0; i < kSpiralPointsPerShell; ++i) {
      const glm::vec3 candidate = position + radius * lattice_direction(Lattice::fibonacci, i, kSpiralPointsPerShell);
      if (is_valid_position(ctx, candidate, cube)) return candidate;
    }
  }
  return std::nullopt;
}

} // namespace probebake::placement
