// Helpers shared by the placement methods' folders (placement/methods/<name>/; not part of the interface).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "probebake/formats/octree.h"
#include "probebake/placement/placement.h"

namespace probebake::placement::detail {

// Traces the lattice from positions[i] within cubes[i], in parallel (in.settings.threads), in index order.
std::vector<ProbeRays> trace_all(const PlacementInput& in, const std::vector<Cube>& cubes,
                                 const std::vector<glm::vec3>& positions);

} // namespace probebake::placement::detail
