// Skeleton probe placement (nonuniform-probe-placement-svo.txt §3.1-3.3): probes on the medial axis of
// the scene's free space, selected greedily by the surface each one sees and moved by a sampled gradient
// ascent of the paper's visibility objective.
//
//  1. Distance grid: the scene's signed distance (SceneSdf, OpenVDB) sampled at voxel centres over the
//     placement domain. Free voxels are at least the clearance from every surface.
//  2. Skeleton: free voxels on a ridge of the distance (along one of the 13 axes of the 26-neighbourhood,
//     not below either neighbour and half a voxel above the shallower one), the discrete medial axis:
//     points with two or more nearest surfaces. A ridge test, not a topology-preserving thinning: the
//     candidates need the axis's points, not its connectivity.
//  3. Candidates: skeleton voxels thinned to a Poisson-disc subset, deepest (largest distance) first.
//  4. Selection: greedy over candidates against surface samples (area-uniform, fixed seed). Objective
//     R(P) = sum over samples s of max over probes k of q(k, s), with q = visibility * cos at the surface
//     (the paper's solid-angle term) * l^2 / (l^2 + d^2). The paper's distance term rewards *far* probes
//     (its ray marcher); ours serves irradiance interpolation, which wants near probes, so it falls off
//     with distance over l (0.6 x the probe spacing the budget allows, measured). Without a budget, probes are added
//     until no candidate sees a sample no chosen probe sees (full coverage, the paper's minimal set).
//  5. Optimisation (paper §3.3): each probe in turn tries the 8 corners of a cube of half-size `step`
//     around it (randomly rotated per probe and round: the paper's stochastic direction sampling) and
//     moves to the best if R grows; the step halves every round. The paper's Gibbs acceptance accepts a
//     single-probe move with probability R(P')/R(P), which is ~1 for one probe among many (a random
//     walk); we accept only improvements, so R never decreases.
//
// Deterministic: seeded, and every parallel loop writes its own slot, so the result is bit-identical for
// any thread count. Units: scene units (metres).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/scene/ray_scene.h"
#include "probebake/placement/scene_sdf.h"
#include "surface_samples.h" // SurfaceSample, sample_surface: shared with refine_root.cpp

namespace probebake::placement {

struct SkeletonOptions {
  int probes = 0;         // budget; 0 = the fewest that see every sample any candidate sees
  float clearance = 0.0f; // minimum probe-to-surface distance (> 0)
  // Probes stay inside it (the root cube). Empty = the scene's bounds padded by 3 x clearance on every
  // side, so that a solid filling its own bounds (box_draco) still has free space around it.
  scene::Bounds domain;
  float voxel_size = 0.0f;    // distance grid; 0 = the domain's largest extent / 64
  int surface_samples = 2048; // objective samples over the surface area
  int max_candidates = 1024;  // skeleton candidates kept for the greedy selection (at least 4x the budget)
  int iterations = 4;         // optimisation rounds (0 = none)
  // With a budget, l = falloff_scale * sqrt(surface area / probes). Measured on the Cornell box at 124
  // probes (probebake eval, relative RMSE): 0.3 -> 0.080, 0.4 -> 0.100, 0.5 -> 0.068, 0.6 -> 0.068,
  // 0.7 -> 0.069, 1 -> 0.095, 2 -> 0.095, 3 -> 0.124 (noisy below 0.5: one bad probe sets the RMSE).
  float falloff_scale = 0.6f;
  std::uint64_t seed = 1;
  int threads = 0; // 0 = all cores
};

struct SkeletonReport {
  int free_voxels = 0;
  int skeleton_voxels = 0;
  int candidates = 0;
  float coverage = 0.0f;           // samples the probes see / samples any candidate sees
  double objective_selected = 0.0; // R after selection
  double objective_final = 0.0;    // R after optimisation (>= objective_selected)
  int moves = 0;                   // accepted optimisation moves
};

struct SkeletonResult {
  std::vector<glm::vec3> probes; // selection order
  SkeletonReport report;
};

// SkeletonOptions::domain when left empty.
scene::Bounds default_domain(const scene::Scene& scene, float clearance);

// The SceneSdf settings the skeleton needs: a band wide enough that free space is not saturated (the
// ridges are where the distance peaks), at half the domain's largest extent.
SdfSettings skeleton_sdf_settings(const scene::Bounds& domain);

// Places the probes. `rays` and `sdf` are of the same scene. Throws probebake::Error (usage) for bad
// options. Returns no probe when the domain holds no free voxel.
SkeletonResult skeleton_probes(const scene::RayScene& rays, const SceneSdf& sdf, const SkeletonOptions& options);

// ---- Building blocks (tests measure each) ------------------------------------------------------------

struct DistanceGrid {
  glm::vec3 origin{0.0f}; // centre of voxel (0, 0, 0)
  float voxel = 0.0f;
  glm::ivec3 dims{0};
  std::vector<float> distance; // x fastest
  glm::vec3 centre(glm::ivec3 v) const { return origin + glm::vec3(v) * voxel; }
  std::size_t index(glm::ivec3 v) const {
    return (std::size_t(v.z) * std::size_t(dims.y) + std::size_t(v.y)) * std::size_t(dims.x) + std::size_t(v.x);
  }
  glm::ivec3 voxel_of(std::size_t i) const;
};

DistanceGrid sample_distance(const SceneSdf& sdf, const scene::Bounds& domain, float voxel, int threads);

// Indices (DistanceGrid::index) of the ridge voxels at least `clearance` from every surface, ascending.
std::vector<std::size_t> skeleton_voxels(const DistanceGrid& grid, float clearance);

// q(p, s) of the objective: 0 when the sample faces away or is occluded, else cos * l^2 / (l^2 + d^2).
float sample_quality(const scene::RayScene& rays, glm::vec3 probe, const SurfaceSample& s, float falloff);

// Fraction of the samples seen (q > 0) by some probe, among those seen by some point of `reference`.
float coverage(const scene::RayScene& rays, const std::vector<glm::vec3>& probes,
               const std::vector<glm::vec3>& reference, const std::vector<SurfaceSample>& samples, int threads);

} // namespace probebake::placement
