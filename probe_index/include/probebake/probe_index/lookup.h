// Irradiance lookup from a baked probe volume: the CPU reference that the Vulkan runtime reproduces
// step for step. Probes store L2 spherical harmonics of irradiance (gpu_types.h, Probe::irradiance_sh):
// light reflected by surfaces (and sky), without punctual lights and - with the default
// LightingSettings::emissive_as_lights - without the emitters' own radiance; a renderer adds both per
// pixel with direct_irradiance() (lighting.h, algorithm in docs/LIGHTING.md). The lookup itself does not
// depend on that setting.
//
// References: DDGI smooth back-face weight (Majercik et al. 2019, as discussed in the DDGI relocation
// paper, /work/shared/papers/ddgi-probe-relocation.txt §2.1); SVO probe index (non-uniform placement paper
// §4.1); the all-probes baseline is the octree thesis's closest-hit shading (§3.2.4).
//
// ---- SH convention (shared with the GPU) -------------------------------------------------------------
// Real SH, coefficient k = l^2 + l + m, with (x, y, z) a unit direction:
//   k=0 Y00  = 0.282095
//   k=1 Y1-1 = 0.488603 y     k=2 Y10 = 0.488603 z     k=3 Y11 = 0.488603 x
//   k=4 Y2-2 = 1.092548 xy    k=5 Y2-1 = 1.092548 yz   k=6 Y20 = 0.315392 (3z^2 - 1)
//   k=7 Y21  = 1.092548 xz    k=8 Y22 = 0.546274 (x^2 - y^2)
// irradiance_sh[3k + c] (c = R, G, B) holds the coefficients of irradiance E(n) = sum_k sh_k Y_k(n): the
// radiance's coefficients already multiplied by the clamped-cosine factors A_0 = pi, A_1 = 2pi/3,
// A_2 = pi/4 (Ramamoorthi & Hanrahan 2001). Evaluation is a 9-term dot product per channel.
//
// ---- SVO mode (sample_irradiance) --------------------------------------------------------------------
//  1. p' = position + normal * bias, bias = 0.5 * root_size / 2^svo_depth (half an SVO voxel v), so that
//     points on a surface look up the open voxel in front of it, not one marked solid. p' outside the root
//     cube (max faces included) or not finite is a miss: the result is (0,0,0).
//  2. Leaf stencil of a leaf: for each used slot k (probes[k] >= 0): d = probe.position - position,
//     dir = d * inversesqrt(max(dot(d, d), 1e-30)) (a zero vector when the probe sits on the point),
//     w_k = weights[k] * (((dot(normal, dir) + 1) / 2)^2 + 0.05)   (smooth back-face weight);
//     the stencil holds w_k / sum w (empty when sum w == 0). E_leaf = sum_k (w_k / sum w) * max(0, E_k(normal)),
//     E_k = SH evaluation of probe k, clamped per channel.
//  3. Blend (issue #39: a leaf's stencil is constant inside it, so leaf borders showed as steps). The eight
//     finest-voxel centres q_c around p' (g = (p' - root_min) / v - 0.5, lo = floor(g), f = g - lo; indices
//     clamped to the root cube) each look up their leaf by descent from node 0 (v = svo_nodes[node]; v > 0:
//     node = v + octant, octant bit 0 = x bit, 1 = y, 2 = z, from the top; v < 0: leaf ~v; v == 0: none).
//     Corner weight = trilinear weight * side, side = clamp(dot(q_c - position, normal) / bias, 0, 1): a
//     centre behind the surface's plane may lie past a thin wall and does not blend in. Corners without a
//     leaf or whose leaf cannot serve (no probe in range with a positive stored weight) drop out; the weights of corners sharing a leaf add up, the leaves
//     kept in first-corner order (corner = x + 2y + 4z bits). The root is p''s own leaf when it can serve, else the corner leaf of largest weight (the first on ties; none: a miss). Only leaves joined
//     to the root by a chain of leaves that share a stored probe (probes[k] >= 0 equal) stay, in their
//     order: leaves across a wall or in a sealed cavity hold other probes and do not blend in. The
//     weights are normalised by their sum; when none stays, the root serves alone.
//     When all eight centres lie in p''s own leaf the result is that leaf's E_leaf (the fast path: one
//     descent, the same value the eight would give).
//  4. E = sum over the blend's leaves of weight * E_leaf, evaluated probe by probe: each probe of the leaves
//     once (first-read order: leaves in blend order, slots in leaf order; its back-face weight computed
//     once), with weight = sum over leaves of leaf weight * (w_k / sum w) of that leaf, then
//     E = sum_j weight_j * max(0, E_j(normal)). A leaf whose sum w is 0 adds nothing. Neighbouring leaves
//     share most probes: 5 leaves read ~7 probes, not 20. The result is continuous across leaf borders,
//     octree levels and cells (each corner weight is continuous in position); inside a leaf farther than
//     half a finest voxel from its faces it equals the leaf's stencil.
// The bake's light transport (hit_cache.h) and the runtime light update look bounce light up with one
// leaf stencil (svo_stencil: steps 1-2 at p''s leaf): a seam at a bounce hit averages over the probe's rays.
//
// ---- All-probes mode (sample_irradiance_all_probes, the thesis's §3.2.4 baseline) -----------------------
// Same p' and clamped SH evaluation; every live probe (link != 0) whose segment from p' is not occluded
// (Embree ray p' -> probe) gets w = (((dot(normal, dir) + 1) / 2)^2 + 0.05) / max(dot(d, d), bias^2),
// then E = sum w E_k / sum w. O(probes) rays per lookup: a baseline for comparisons, not for runtimes.
//
// Thread-safety: all functions are pure (the stats pointer is written only by the calling thread).
#pragma once

#include <array>
#include <cstddef>
#include <span>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <glm/ext/vector_int4.hpp>

#include "probebake/scene/ray_scene.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::probe_index {

// ---- Spherical harmonics ----------------------------------------------------------------------------------
// The basis constants, defined once for C++ and GLSL in gpu_types.h (sh.glsl uses the same).
inline constexpr float kShY0 = gpu::SH_Y0;   // 1 / (2 sqrt(pi))
inline constexpr float kShY1 = gpu::SH_Y1;   // sqrt(3 / (4 pi))
inline constexpr float kShY2 = gpu::SH_Y2;   // sqrt(15 / (4 pi))
inline constexpr float kShY20 = gpu::SH_Y20; // sqrt(5 / (16 pi))
inline constexpr float kShY22 = gpu::SH_Y22; // sqrt(15 / (16 pi))
// Clamped-cosine convolution factors A_l per band: irradiance coefficient = A_l * radiance coefficient.
inline constexpr float kShBand0 = gpu::SH_BAND0; // pi
inline constexpr float kShBand1 = gpu::SH_BAND1; // 2 pi / 3
inline constexpr float kShBand2 = gpu::SH_BAND2; // pi / 4

// The nine basis values at unit direction `d`, in the order above.
std::array<float, 9> sh_basis(glm::vec3 d);
// Irradiance of one probe's coefficients at unit normal `n`, per channel, not clamped.
glm::vec3 evaluate_sh(const float* sh27, glm::vec3 n);

// ---- SVO lookup ------------------------------------------------------------------------------------------
// Up to four probes and their final, normalised weights (unused slots: probe -1, weight 0). A lookup
// that missed has no used slot.
struct ProbeStencil {
  glm::ivec4 probes{-1};
  glm::vec4 weights{0.0f};
  bool empty() const { return probes.x < 0; }
};

struct SamplerStats {
  std::size_t samples = 0;
  std::size_t misses = 0; // lookups that found no probe (empty voxel, outside the root cube, none visible)
};

// The leaves a blended lookup (steps 1 and 3) reads and their normalised weights; count 0 is a miss.
struct BlendedLookup {
  std::array<int, 8> leaves{};
  std::array<float, 8> weights{};
  int count = 0;
  void add(int leaf, float weight); // adds to the entry of the same leaf, else appends
  BlendedLookup normalised() const;
};

// The probes a blended lookup reads, each once, with their final weights (step 4): the sum over the blend's
// leaves of leaf weight * the probe's normalised stencil weight in that leaf. Probes in first-read order
// (leaves in blend order, slots in leaf order).
struct ProbeBlend {
  static constexpr int kCapacity = 8 * gpu::SVO_PROBES_PER_LEAF;
  std::array<int, kCapacity> probes{};
  std::array<float, kCapacity> weights{};
  int count = 0;
};

// A leaf can serve a lookup: it holds a probe in range with a positive stored weight (its stencil is then
// not empty, the back-face weight being at least 0.05).
bool leaf_serves(const formats::ProbeVolume& volume, int leaf);

// Half an SVO voxel: the normal bias of step 1.
float normal_bias(const gpu::VolumeInfo& info);
// Step 2: index into volume.svo_leaves of the leaf containing `p`, or -1 (empty node, outside the root
// cube, no SVO, non-finite point). `leaf_depth`, when given, receives the leaf node's depth (root 0; the
// SVO merges uniform regions into shallower leaves).
int find_svo_leaf(const formats::ProbeVolume& volume, glm::vec3 p, int* leaf_depth = nullptr);
// Step 2 for leaf `leaf` (empty for -1 or an index out of range).
ProbeStencil leaf_stencil(const formats::ProbeVolume& volume, int leaf, glm::vec3 position, glm::vec3 normal);
// Steps 1-2 at p''s own leaf: the stencil of the bounce transport.
ProbeStencil svo_stencil(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal);
// Steps 1 and 3.
BlendedLookup blended_lookup(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal);
// Step 4's weights: each probe of the blend's leaves once.
ProbeBlend probe_blend(const formats::ProbeVolume& volume, const BlendedLookup& lookup, glm::vec3 position,
                       glm::vec3 normal);
// E = sum_j weight_j * max(0, E_j(normal)) over the probe blend.
glm::vec3 apply_blend(const formats::ProbeVolume& volume, const ProbeBlend& blend, glm::vec3 normal);
// E_leaf of step 2 for a stencil, with the volume's probes.
glm::vec3 apply_stencil(const formats::ProbeVolume& volume, const ProbeStencil& stencil, glm::vec3 normal);

// ---- Lookups ---------------------------------------------------------------------------------------------
// Irradiance (W/m^2) arriving at a surface point with unit `normal` from the surfaces the probes saw
// (emitted and reflected light; punctual lights are not in the probes, see docs/LIGHTING.md).
glm::vec3 sample_irradiance(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal,
                            SamplerStats* stats = nullptr);
glm::vec3 sample_irradiance_all_probes(const formats::ProbeVolume& volume, const scene::RayScene& rays,
                                       glm::vec3 position, glm::vec3 normal, SamplerStats* stats = nullptr);

// Batch forms: out[i] for (positions[i], normals[i]), in parallel (0 threads = all cores); the results
// do not depend on the thread count. The spans must have equal sizes (Error(internal) otherwise).
void sample_irradiance(const formats::ProbeVolume& volume, std::span<const glm::vec3> positions,
                       std::span<const glm::vec3> normals, std::span<glm::vec3> out, SamplerStats* stats = nullptr,
                       int threads = 0);
void sample_irradiance_all_probes(const formats::ProbeVolume& volume, const scene::RayScene& rays,
                                  std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                                  std::span<glm::vec3> out, SamplerStats* stats = nullptr, int threads = 0);

} // namespace probebake::probe_index
