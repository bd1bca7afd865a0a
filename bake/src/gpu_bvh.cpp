// rtcBuildBVH into temporary build nodes (allocated by Embree, freed with the RTCBVH), then flattened
// depth-first into gpu::BvhNode with the two children of every inner node adjacent. Only the topology is
// kept: formats::TraceMeshBuilder computes the boxes from the corners and quantises them.
#include "gpu_bvh.h"

#include <algorithm>
#include <limits>
#include <new>
#include <utility>

#include <embree3/rtcore.h>
#include <embree3/rtcore_builder.h>
#include <fmt/core.h>
#include <glm/common.hpp>

#include "probebake/common/parallel.h"
#include "probebake/formats/error.h"

namespace probebake::bake::detail {
namespace {

// Embree's depth limit: below BVH_MAX_DEPTH (the shaders' stack) with room to spare. Embree turns the
// last levels into a small tree of leaves instead of going deeper.
constexpr unsigned kMaxBuildDepth = 40;

// Build nodes live in Embree's thread-local allocator memory: trivially destructible, never deleted.
struct BuildNode {
  bool leaf = false;
};

struct InnerBuildNode : BuildNode {
  BuildNode* children[2] = {nullptr, nullptr};
};

struct LeafBuildNode : BuildNode {
  unsigned count = 0;
  unsigned triangles[gpu::TRACE_MAX_LEAF_FACES] = {};
};

// Set from the callbacks when Embree hands us something a binary BVH with small leaves cannot hold;
// checked after the build (exceptions must not cross Embree's C interface).
struct BuildState {
  bool unexpected = false;
};

void* create_node(RTCThreadLocalAllocator allocator, unsigned child_count, void* user) {
  if (child_count != 2) static_cast<BuildState*>(user)->unexpected = true;
  void* memory = rtcThreadLocalAlloc(allocator, sizeof(InnerBuildNode), 16);
  return memory == nullptr ? nullptr : new (memory) InnerBuildNode;
}

void set_children(void* node, void** children, unsigned child_count, void* user) {
  auto* inner = static_cast<InnerBuildNode*>(node);
  if (child_count != 2) static_cast<BuildState*>(user)->unexpected = true;
  for (unsigned i = 0; i < std::min(child_count, 2u); ++i) inner->children[i] = static_cast<BuildNode*>(children[i]);
}

void set_bounds(void*, const RTCBounds**, unsigned, void*) {} // boxes are refitted from the triangles

void* create_leaf(RTCThreadLocalAllocator allocator, const RTCBuildPrimitive* primitives, size_t count, void* user) {
  void* memory = rtcThreadLocalAlloc(allocator, sizeof(LeafBuildNode), 16);
  if (memory == nullptr) return nullptr;
  auto* leaf = new (memory) LeafBuildNode;
  leaf->leaf = true;
  if (count < 1 || count > std::size_t(gpu::TRACE_MAX_LEAF_FACES)) static_cast<BuildState*>(user)->unexpected = true;
  leaf->count = unsigned(std::min<std::size_t>(count, gpu::TRACE_MAX_LEAF_FACES));
  for (unsigned i = 0; i < leaf->count; ++i) leaf->triangles[i] = primitives[i].primID;
  return leaf;
}

std::vector<RTCBuildPrimitive> build_primitives(std::span<const formats::TraceInputTriangle> triangles) {
  std::vector<RTCBuildPrimitive> primitives(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    glm::vec3 lower = triangles[i].corners[0], upper = lower;
    for (int k = 1; k < 3; ++k)
      lower = glm::min(lower, triangles[i].corners[k]), upper = glm::max(upper, triangles[i].corners[k]);
    primitives[i] = RTCBuildPrimitive{lower.x, lower.y, lower.z, 0u, upper.x, upper.y, upper.z, unsigned(i)};
  }
  return primitives;
}

// Depth-first, children adjacent: a node's children get the next two free slots when it is visited.
GpuBvh flatten(const BuildNode* root) {
  GpuBvh bvh;
  bvh.nodes.push_back(gpu::BvhNode{});
  std::vector<std::pair<const BuildNode*, int>> stack{{root, 0}};
  std::vector<int> depth{0};
  while (!stack.empty()) {
    const auto [node, index] = stack.back();
    stack.pop_back();
    bvh.depth = std::max(bvh.depth, depth[std::size_t(index)]);
    gpu::BvhNode& out = bvh.nodes[std::size_t(index)];
    if (node->leaf) {
      const auto* leaf = static_cast<const LeafBuildNode*>(node);
      out.first = int(bvh.leaf_order.size());
      out.count = int(leaf->count);
      bvh.leaf_order.insert(bvh.leaf_order.end(), leaf->triangles, leaf->triangles + leaf->count);
      continue;
    }
    const auto* inner = static_cast<const InnerBuildNode*>(node);
    const int first = int(bvh.nodes.size());
    out.first = first;
    out.count = 0;
    bvh.nodes.resize(bvh.nodes.size() + 2);
    depth.resize(bvh.nodes.size(), depth[std::size_t(index)] + 1);
    stack.emplace_back(inner->children[1], first + 1); // the first child is visited first
    stack.emplace_back(inner->children[0], first);
  }
  return bvh;
}

class EmbreeBvh {
public:
  EmbreeBvh() {
    device_ = rtcNewDevice(nullptr); // built on one thread (build()): the same tree on every run
    if (device_ == nullptr) throw Error(ErrorKind::internal, "gpu_scene: Embree: rtcNewDevice failed");
    bvh_ = rtcNewBVH(device_);
  }
  ~EmbreeBvh() {
    if (bvh_ != nullptr) rtcReleaseBVH(bvh_);
    rtcReleaseDevice(device_);
  }
  EmbreeBvh(const EmbreeBvh&) = delete;
  EmbreeBvh& operator=(const EmbreeBvh&) = delete;

  const BuildNode* build(std::vector<RTCBuildPrimitive>& primitives, float leaf_cost, unsigned max_depth) {
    BuildState state;
    RTCBuildArguments args = rtcDefaultBuildArguments();
    args.buildQuality = RTC_BUILD_QUALITY_HIGH; // binned SAH; no splitPrimitive: each triangle in one leaf
    args.maxBranchingFactor = 2;
    args.maxDepth = max_depth;
    args.minLeafSize = 1;
    args.intersectionCost = leaf_cost; // Embree's default is 1; lower gives larger leaves
    args.maxLeafSize = unsigned(gpu::TRACE_MAX_LEAF_FACES);
    args.bvh = bvh_;
    args.primitives = primitives.data();
    args.primitiveCount = primitives.size();
    args.primitiveArrayCapacity = primitives.size();
    args.createNode = create_node;
    args.setNodeChildren = set_children;
    args.setNodeBounds = set_bounds;
    args.createLeaf = create_leaf;
    args.userPtr = &state;
    const BuildNode* root = nullptr;
    run_on_one_thread([&] { root = static_cast<const BuildNode*>(rtcBuildBVH(&args)); });
    if (root == nullptr || state.unexpected || rtcGetDeviceError(device_) != RTC_ERROR_NONE) {
      throw Error(ErrorKind::internal,
                  fmt::format("gpu_scene: Embree: rtcBuildBVH failed (error {}{})", int(rtcGetDeviceError(device_)),
                              state.unexpected ? ", unexpected node shape" : ""));
    }
    return root;
  }

private:
  RTCDevice device_ = nullptr;
  RTCBVH bvh_ = nullptr;
};

} // namespace

GpuBvh build_gpu_bvh(std::span<const formats::TraceInputTriangle> triangles, float leaf_cost, int depth_above) {
  if (triangles.empty()) return {};
  if (depth_above < 0 || depth_above >= int(kMaxBuildDepth))
    throw Error(ErrorKind::internal, fmt::format("gpu_scene: a subtree starts at depth {}, past the build limit {}",
                                                 depth_above, kMaxBuildDepth));
  std::vector<RTCBuildPrimitive> primitives = build_primitives(triangles);
  EmbreeBvh embree;
  GpuBvh bvh = flatten(
      embree.build(primitives, leaf_cost, kMaxBuildDepth - unsigned(depth_above))); // the build nodes die with `embree`
  bvh.depth += depth_above;
  if (bvh.depth >= gpu::BVH_MAX_DEPTH) {
    throw Error(ErrorKind::internal,
                fmt::format("gpu_scene: BVH depth {} reaches BVH_MAX_DEPTH {}", bvh.depth, gpu::BVH_MAX_DEPTH));
  }
  return bvh;
}

} // namespace probebake::bake::detail
