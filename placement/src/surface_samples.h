// Points on the scene's surfaces, spread by area (the skeleton method's objective samples, and the root
// cube's open-space test in refine_root.cpp), and the deterministic hash they are drawn with.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/scene/scene.h"

namespace probebake::placement {

struct SurfaceSample {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f}; // the side that is seen (a double-sided triangle gives samples on both sides)
};

// Area-uniform stratified samples on every triangle side that can be seen (fronts; both sides of
// double-sided triangles).
std::vector<SurfaceSample> sample_surface(const scene::Scene& scene, int count, std::uint64_t seed);

// Deterministic uniform [0, 1) from (seed, stream, index).
float hash_uniform(std::uint64_t seed, std::uint64_t stream, std::uint64_t index);

} // namespace probebake::placement
