// Helpers shared by the placement methods' files (not part of the interface).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/formats/octree.h"
#include "probebake/placement/placement.h"

namespace probebake::placement::detail {

// The octree's loose overlap test (octree.cpp, refine_octree.cpp): the bounding box of triangle `t`
// overlaps the cube, faces included.
bool box_overlaps_cube(const scene::Scene& s, std::uint32_t t, const formats::NodeCube& cube);

// Traces the lattice from positions[i] within cubes[i], in parallel (in.settings.threads), in index order.
std::vector<ProbeRays> trace_all(const PlacementInput& in, const std::vector<Cube>& cubes,
                                 const std::vector<glm::vec3>& positions);

} // namespace probebake::placement::detail
