// Placement candidates for the error-driven octree refinement (refine_octree.h): one trace per
// candidate gives the placement's hit measurements and a cheap irradiance estimate, so that a leaf's
// split can be scored by how much its children's light differs from its own.
#pragma once

#include <array>

#include <glm/vec3.hpp>

#include "probebake/lighting/direct_light.h"
#include "probebake/placement/placement.h"

namespace probebake::placement {

struct CandidateSample {
  ProbeRays rays; // the placement's measurements (hit fraction, dead-probe test)
  // L1 SH of the irradiance E(n) = sum_k sh[k] Y_k(n) (lookup.h's basis, k < 4) from one bounce of the
  // direct light (the lighting stage's first sweep), RGB. Probes hold reflected light only: punctual
  // lights and emitters are added per pixel and would only hide the part probes carry.
  std::array<glm::vec3, 4> sh{};
  float visible_area = 0.0f; // surface area inside the cube seen from its centre (m^2)

  bool inside() const { return rays.backface_fraction() > 0.5f; }
};

// Thread-safe after construction. Emitters are sampled with a few patches (kEstimateEmitterSamples),
// enough to rank leaves, not to light probes.
class CandidateSampler {
public:
  // `estimate`: compute the irradiance estimate (sh); else only rays and visible_area.
  CandidateSampler(const PlacementInput& in, bool estimate);
  CandidateSample sample(glm::vec3 position, const Cube& cube) const;
  // Whether anything emits light (punctual lights, emissive triangles, sky): else every estimate is 0.
  bool lit() const { return lit_; }

private:
  const PlacementInput& in_;
  lighting::detail::DirectLighting direct_;
  lighting::LightingSettings lighting_;
  std::vector<glm::vec3> light_directions_;
  bool lit_ = false;
  bool estimate_ = true;
};

// Squared L2 distance between two L1 irradiance SH (sum over channels): the integral over the sphere
// of normals of the squared irradiance difference (the basis is orthonormal).
float sh_distance2(const std::array<glm::vec3, 4>& a, const std::array<glm::vec3, 4>& b);

} // namespace probebake::placement
