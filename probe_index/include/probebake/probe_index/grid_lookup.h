// The grid engine's lookup (issue #41): how Unity's Adaptive Probe Volumes and RTXGI-DDGI read a uniform
// grid, on a grid bake's lattice (format 1.8, formats/grid_lattice.h). No index is searched: the cell is
// found by arithmetic and its eight corner probes blend trilinearly.
//
//  1. p' = position + normal * bias, bias = a quarter of the smallest lattice spacing (DDGI's normal bias).
//  2. g = (p' - origin) / spacing - 0.5 (lattice coordinates); the cell's lowest corner is c = clamp(floor(g), 0, n - 2) and
//     f = clamp(g - c, 0, 1) per axis (outside the lattice the border cell's value extends: no miss).
//  3. Corner k (bit 0: +x, 1: +y, 2: +z) is lattice point q = c + bits(k); it takes part when its point names a
//     live probe. Its weight is w_k = trilinear(f, k) * serve_k * reach_k * side_k:
//     - serve_k: the point's cell bits (the bake sets bit o when the probe sees the cell on side o, build.h,
//       build_grid_lattice: probes inside solids and behind walls that cross no cell stay out) blended
//       trilinearly over the centres of the eight cells around q, at g - q, so that it changes smoothly where p'
//       passes from one of q's cells into the next (on the lattice's border the missing side takes the present
//       side's bits);
//     - reach_k = product over the axes a of clamp((r_a - |o_a|) / 0.125 + 0.5, 0, 1), o = (p' - probe) /
//       spacing and r_a the probe's reach along the axis towards p' (GridPoint::reach, in spacings): a probe
//       does not light points past the first surface it sees along an axis (a wall or a light fixture's shell
//       through the cell), with a ramp of an eighth of a spacing centred on that surface;
//     - side_k = clamp(dot(probe - position, normal) / bias, 0, 1): a probe behind the surface's plane does not
//       light it.
//     As the weights vanish (their sum W below 0.01) a floor fades in: w_k + (1 - W / 0.01) * serve_k *
//     (trilinear * reach + 0.001) * (side + 0.001), so that a point whose probes all lie behind it is lit by
//     them rather than left black (DDGI's weight floor), without a step where the floor starts.
//  4. E = sum_k w_k max(0, E_k(normal)) / sum_k w_k, E_k the probe's SH irradiance clamped per channel.
// A zero normal asks for a point in a volume (fog, particles): no bias, every side weight 1, and E_k(0) is
// the probe's mean irradiance over directions (the constant SH term).
// Every weight is continuous in the position, so the lookup is continuous across cell borders. Where the
// corners of non-zero trilinear weight serve fully and lie at least `bias` in front of the surface (every
// volume lookup away from geometry), the result is the trilinear interpolation of their irradiance at p': a
// field linear in position is reproduced exactly. The reach test stops light through walls along the axes; a
// surface that crosses no probe's axis rays (a slanted or small one) can still let light through within a
// cell, as in grid engines.
#pragma once

#include <array>
#include <optional>

#include <glm/vec3.hpp>

#include "probebake/formats/grid_lattice.h"
#include "probebake/probe_index/lookup.h"

namespace probebake::probe_index {

// The corners of a lookup that serve it and their normalised weights (count 0: a miss).
struct GridCorners {
  std::array<int, 8> probes{};
  std::array<float, 8> weights{};
  int count = 0;
};

// Step 1's bias.
float grid_normal_bias(const gpu::GridLatticeHeader& header);
// Steps 1-3 (a miss when the lattice is absent or malformed, or the point or normal is not finite).
GridCorners grid_corners(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal);
// Steps 1-4. A volume without a lattice misses everywhere.
glm::vec3 sample_irradiance_grid(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal,
                                 SamplerStats* stats = nullptr);

} // namespace probebake::probe_index
