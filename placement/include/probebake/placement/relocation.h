// Dead-probe relocation (DDGI relocation paper §3.1-3.2): a probe inside geometry, or closer to a surface
// than the clearance, is moved to a position inside its own cube that is outside geometry and at least
// the clearance away from every surface, or reported as impossible (the caller frees it).
#pragma once

#include <optional>
#include <span>

#include "probebake/placement/probe_tracing.h"

namespace probebake::placement {

class SceneSdf;

struct RelocationContext {
  const scene::RayScene* rays = nullptr;
  const SceneSdf* sdf = nullptr;         // geometry-aware direction; may be null
  std::span<const glm::vec3> directions; // the probe lattice, used to verify candidates
  float clearance = 0.0f;
};

// Candidates, in order: along the SDF gradient to the clearance; through the nearest surface along its
// normal (from the probe's own rays); then a deterministic spiral of shells around the probe.
std::optional<glm::vec3> relocate_probe(const RelocationContext& ctx, glm::vec3 position, const ProbeRays& rays,
                                        const Cube& cube);

// True when `p` is a valid probe position: inside the cube and alive (not dead) at the clearance.
bool is_valid_position(const RelocationContext& ctx, glm::vec3 p, const Cube& cube);

} // namespace probebake::placement
