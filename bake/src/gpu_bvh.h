// The BVH of the runtime lighting sections (gpu::BvhNode, docs/FORMAT.md): built with Embree's
// rtcBuildBVH (binned SAH, binary, at most BVH_MAX_LEAF_TRIANGLES per leaf) into our own layout, which the
// runtime's shaders traverse without ray-tracing extensions.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "probebake/gpu_types.h"

namespace probebake::bake::detail {

struct GpuBvh {
  std::vector<gpu::BvhNode> nodes;         // root at 0, depth-first, the two children of a node adjacent
  std::vector<std::uint32_t> leaf_order;   // triangle k of the leaves = input triangle leaf_order[k]
  int depth = 0;                           // deepest node (root = 0)
};

// The tree over `triangles` (their v0, edge1, edge2 are used). Node boxes are the exact float bounds of
// v0, v0 + edge1 and v0 + edge2 of the triangles below. Deterministic: Embree builds on one thread.
// Empty input gives an empty tree. Throws Error(internal) when Embree fails or the tree reaches
// BVH_MAX_DEPTH.
GpuBvh build_gpu_bvh(std::span<const gpu::TraceTriangle> triangles);

} // namespace probebake::bake::detail
