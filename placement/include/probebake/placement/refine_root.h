// The root cube of a scene that is one closed object seen from outside (box_draco: a unit cube, single-
// sided, faces out): the bounds' bounding cube lies wholly inside the solid, every candidate probe is
// dead and none can be moved out within its cube, so the bake placed none. Such a scene gets a root
// cube three times its size around the same centre, so that probes can surround the object (with two,
// the object's faces lie 1 mm inside the cube boundaries of every level: no outer leaf overlaps them).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "probebake/scene/ray_scene.h"
#include "probebake/gpu_types.h"

namespace probebake::placement {

// Whether the scene has open space (is_open at `clearance` over `directions`, the test the eval's viewpoints
// use) inside the root cube: at a centre of a kOpenProbeCells^3 grid over the root cube, at one of a grid
// over the scene's bounds, or, inside the bounds, halfway between a point of its surfaces (512, spread by
// area) and what that point's face sees along its normal. The bounds' grid finds the rooms of a flat world,
// whose 3 m of height the root cube's grid (one point per eighth of its width) passes over: the 64 rooms
// side by side of a world 49 m wide were taken for a closed object and baked in a root three times too
// wide. The surface points find them when no grid point is far enough from every surface, as at the default
// clearance (0.99 m there, where the bake placed no probe).
bool open_space_inside(const scene::RayScene& rays, const gpu::VolumeInfo& info, const scene::Bounds& bounds,
                       float clearance, const std::vector<glm::vec3>& directions, int threads);

// The root cube scaled by kSurroundScale about its centre.
void surround_root(gpu::VolumeInfo& info);

} // namespace probebake::placement
