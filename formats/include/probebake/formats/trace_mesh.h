// The compact tracing sections (format 1.4, gpu_types.h "Compact tracing"): building them from a binary
// BVH over triangles, upgrading a 1.1-1.3 volume's float layout to them, and reading a face back on the
// CPU exactly as the shaders do (shaders/include/probebake/bvh_trace.glsl).
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/formats/probe_volume.h"
#include "probebake/gpu_types.h"

namespace probebake::formats {

// A triangle to trace: its corners (counter-clockwise front face) and surface.
struct TraceInputTriangle {
  glm::vec3 corners[3]{};
  glm::vec3 albedo{0.0f};
  glm::vec3 emission{0.0f};
  bool double_sided = false;
};

// A binary tree over triangles, as a BVH builder gives it: root at nodes[0] (or no node for no triangle);
// an inner node (count 0) has its children at first and first + 1; a leaf (count 1..TRACE_MAX_LEAF_FACES)
// holds triangles [first, first + count) of the leaf-ordered triangle list. Its boxes are not used.
struct TraceTreeInput {
  std::span<const gpu::BvhNode> nodes;
  std::span<const TraceInputTriangle> triangles; // in leaf order
};

// Appends trees to a volume's trace_trees, trace_nodes, trace_faces, trace_vertices and trace_materials,
// sharing vertices (same float bits) and materials (same values) across all of them. Deterministic.
class TraceMeshBuilder {
public:
  explicit TraceMeshBuilder(ProbeVolume& volume);
  // Appends the tree; returns its index in trace_trees. Node boxes are recomputed from the corners and
  // quantised outwards. Throws Error(internal) on a malformed tree or more faces than a child word holds.
  int add_tree(const TraceTreeInput& tree);
  // Appends one tree split by streaming cell (format 1.5): a top level that halves the cells in `top_order`
  // (indices into `cells`; the caller's Morton order keeps neighbours together; cell_top_depths gives where
  // each cell's tree starts), then each cell's inner
  // nodes, faces and vertices in the order of `cells`, contiguous and its own (no vertex shared with any
  // other tree or cell). ranges[k] receives cells[k]'s. Every cell has at least one triangle. Returns the
  // tree's index.
  int add_cell_tree(std::span<const TraceTreeInput> cells, std::span<const std::size_t> top_order,
                    std::vector<CellTracing>& ranges);

private:
  using VertexMap = std::unordered_map<std::uint64_t, std::vector<std::uint32_t>>; // hash of the bits -> indices
  std::uint32_t vertex_in(const glm::vec3& p, VertexMap& vertices);
  std::uint32_t material(const TraceInputTriangle& t);
  gpu::TraceFace face(const TraceInputTriangle& t, VertexMap& vertices); // its vertices shared through `vertices`
  void check_face_room(std::size_t faces) const;

  ProbeVolume& volume_;
  VertexMap vertices_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> materials_; // hash of the values -> indices
};

// The volume holds the float tracing sections of 1.1-1.3 (bvh_nodes, trace_triangles).
inline bool has_float_tracing(const ProbeVolume& v) { return !v.bvh_nodes.empty() || !v.trace_triangles.empty(); }

// A 1.1-1.3 volume (bvh_nodes and trace_triangles) in the compact layout: same trees, same leaf order,
// corners v0, v0 + edge1, v0 + edge2 (within rounding of the stored edges); the float sections are cleared
// and dynamic objects' bvh_root, bvh_node_count and first_triangle point into the new ones. A volume
// without them is left as it is. The volume must have passed validate() (its trees are trusted).
void upgrade_tracing(ProbeVolume& volume);

// The quantised box of `child` (0 or 1) of a node, as the shaders decode it.
struct TraceBox {
  glm::vec3 lower{0.0f}, upper{0.0f};
};
// The depth (root = 0) at which each cell's own tree starts under the top level that
// TraceMeshBuilder::add_cell_tree builds for `cells` cells in `top_order`: a builder keeps each cell's tree
// shallow enough that the whole tree stays under BVH_MAX_DEPTH.
std::vector<int> cell_top_depths(std::span<const std::size_t> top_order);
TraceBox decode_child_box(const gpu::TraceTree& tree, const gpu::TraceNode& node, int child);
// The box of `child` at its smallest over the two roundings a shader may use (lower + q * scale, or one
// fma): what a face must lie in to be found on every device (the validator's trace_tree check).
TraceBox narrowest_child_box(const gpu::TraceTree& tree, const gpu::TraceNode& node, int child);
// The root's box: [lower, lower + TRACE_BOX_STEPS * scale].
TraceBox tree_box(const gpu::TraceTree& tree);

// A face as the shaders intersect it: v0 and the two edges (float subtractions of the stored vertices)
// and the unit normal of their cross product ((0, 0, 1) for a face without area).
struct TraceFaceGeometry {
  glm::vec3 v0{0.0f}, edge1{0.0f}, edge2{0.0f}, normal{0.0f, 0.0f, 1.0f};
};
TraceFaceGeometry face_geometry(const ProbeVolume& volume, std::size_t face);

// Payload bytes of the tracing sections: the float ones of 1.1-1.3 and the compact ones of 1.4.
std::size_t tracing_bytes(const ProbeVolume& volume);

// Child words (TRACE_CHILD_LEAF layout).
inline constexpr bool is_leaf_word(std::uint32_t word) { return (word & gpu::TRACE_CHILD_LEAF) != 0u; }
inline constexpr std::uint32_t leaf_first(std::uint32_t word) { return word & gpu::TRACE_LEAF_FIRST_MASK; }
inline constexpr std::uint32_t leaf_count(std::uint32_t word) {
  return ((word >> gpu::TRACE_LEAF_COUNT_SHIFT) & 15u) + 1u;
}

} // namespace probebake::formats
