// Octree refinement under a probe budget (RefineSettings::probe_budget > 0; the bake's --split-rule
// error or surface).
//
// The hit-fraction rule (octree.cpp, octree thesis §3.2.2) splits where a centre sees much surface
// nearby, which is not where interpolation loses accuracy (the thesis names it its weak point, §5.2.2;
// docs/results/placement.md, "Where the comparison stands", measures it losing to a grid). Here:
//  1. Uniform start: every leaf whose cube overlaps (non-sealed) triangles is split, level by level,
//     while the next level's probe count stays within uniform_share of the budget. A leaf holds a probe
//     when its cube overlaps triangles and its centre sees surface inside the cube (or is inside a solid,
//     for the relocation to move out); leaves of empty space hold none and are never refined.
//  2. Greedy refinement: each probe leaf below max_depth is scored by the error its split would remove,
//     estimated as sum over its eight children c of visible_area(c) * |E_c - E_leaf|^2 (the squared
//     difference of one-bounce L1 irradiance, integrated over normals; refine_sample.h), divided by the
//     probes the split costs. A max-heap pops the best leaves (in fixed batches, ties by node index)
//     while the budget allows; the new children are scored in turn. SplitRule::surface (and an unlit
//     scene) takes the difference as 1: each split gives its probes the most visible surface.
//     Measured (docs/results/placement.md, "Error-driven refinement and a probe budget (issue #13, first
//     bullet)"): surface wins on the Cornell box, error on the leak scene.
// Deterministic for any thread count: samples are computed in parallel into their own slots, every
// decision is sequential.
#pragma once

#include <cstdint>
#include <vector>

#include "probebake/formats/octree.h"
#include "probebake/placement/placement.h"

namespace probebake::placement {

std::vector<PlacedProbe> place_octree_by_error(const PlacementInput& in, formats::Octree& tree);

namespace detail {

// The octree's loose overlap test (octree.cpp, refine_octree.cpp): the bounding box of triangle `t`
// overlaps the cube, faces included.
bool box_overlaps_cube(const scene::Scene& s, std::uint32_t t, const formats::NodeCube& cube);

} // namespace detail

} // namespace probebake::placement
