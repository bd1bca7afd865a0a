// Where the SVO builder (build.cpp) samples a voxel, and the two ray queries it asks of each point.
#pragma once

#include <array>

#include <glm/vec3.hpp>

#include "probebake/scene/ray_scene.h"

namespace probebake::probe_index::detail {

inline constexpr int kVoxelPoints = 9; // the centre and the octants' centres
using Points = std::array<glm::vec3, kVoxelPoints>;
using PointSet = std::array<bool, kVoxelPoints>; // per sample point: in the set

// Inside geometry: most of six axis rays hit back faces of single-sided surfaces (RayHit::inside; the
// back of a double-sided surface is open space).
bool inside_geometry(const scene::RayScene& rays, glm::vec3 p);
// The segment between the points is unoccluded.
bool sees(const scene::RayScene& rays, glm::vec3 from, glm::vec3 to);
// The box's centre and the centres of its eight octants, in that order (a voxel: extent (size, size, size);
// a grid lattice cell: the lattice spacing).
Points voxel_points(glm::vec3 min, glm::vec3 extent);

// The voxel's sample points and which of them lie in open space.
struct VoxelSamples {
  Points points;
  PointSet open;
  bool any_open = false;
};
// voxel_points and which of them are open.
VoxelSamples sample_voxel(const scene::RayScene& rays, glm::vec3 min, glm::vec3 extent);

} // namespace probebake::probe_index::detail
