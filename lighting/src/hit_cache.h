// The probes' rays, traced once (octree thesis §3.2.2 L1/L2: surfels placed once, lit many times). Each
// hit keeps what the iteration needs to re-evaluate its outgoing radiance from new probe values:
//   L = base + reflect * apply_stencil(stencil, normal, probes),
// base = L_e + albedo / pi * E_direct (front hit, or either side of a double-sided surface, with the
// facing normal), the sky's radiance in the ray's direction (miss) or 0 (back of a single-sided surface: inside a solid); reflect =
// albedo / pi for shaded hits, else 0; stencil = the SVO sampler's probes and weights at the hit.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/lighting/lighting.h"
#include "probebake/probe_index/lookup.h"

namespace probebake::lighting::detail {

struct HitRecord {
  glm::vec3 base{0.0f};
  glm::vec3 reflect{0.0f};
  glm::vec3 normal{0.0f};
  probe_index::ProbeStencil stencil;
};

struct HitCache {
  int rays_per_probe = 0;
  std::vector<int> probes;        // live probes, ascending
  std::vector<HitRecord> records; // probe-major: records[i * rays_per_probe + j]
  // projection[j][k] = (4 pi / R) * A_l(k) * Y_k(direction j): radiance of ray j -> irradiance SH.
  std::vector<std::array<float, 9>> projection;
  std::size_t backface_hits = 0; // RayHit::inside(): backs of single-sided surfaces only
  std::size_t misses = 0;
  std::size_t indirect_misses = 0;
};

// Traces every live probe's Fibonacci rays. Throws Error(input) when a hit's base radiance is not finite.
HitCache build_hit_cache(const scene::Scene& scene, const scene::RayScene& rays, const formats::ProbeVolume& volume,
                         const LightingSettings& settings);

} // namespace probebake::lighting::detail
