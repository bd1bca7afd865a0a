// The topology of the runtime's BVHs (docs/FORMAT.md "Compact tracing"): built with Embree's rtcBuildBVH
// (binned SAH, binary, at most TRACE_MAX_LEAF_FACES per leaf); formats::TraceMeshBuilder turns it into the
// compact sections that the shaders traverse without ray-tracing extensions.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "probebake/formats/trace_mesh.h"
#include "probebake/gpu_types.h"

namespace probebake::bake::detail {

struct GpuBvh {
  std::vector<gpu::BvhNode> nodes;       // root at 0, depth-first, the two children of a node adjacent;
                                         // first and count only (boxes are left zero)
  std::vector<std::uint32_t> leaf_order; // triangle k of the leaves = input triangle leaf_order[k]
  int depth = 0;                         // deepest node, counted from the whole tree's root (depth_above)
};

// The tree over `triangles` (their corners are used); `leaf_cost` is the SAH cost of a triangle test
// relative to a node visit (BakeSettings::trace_leaf_cost). Deterministic: Embree builds on one thread.
// Empty input gives an empty tree. Throws Error(internal) when Embree fails or the tree reaches
// BVH_MAX_DEPTH.
// `depth_above`: the depth at which the tree's root sits in a larger tree (a streaming cell's subtree under
// the top level): Embree's depth limit shrinks by it, so that the whole tree stays below BVH_MAX_DEPTH.
GpuBvh build_gpu_bvh(std::span<const formats::TraceInputTriangle> triangles, float leaf_cost, int depth_above = 0);

} // namespace probebake::bake::detail
