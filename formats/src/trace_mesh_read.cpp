// Reading the compact tracing sections back on the CPU (trace_mesh.h): child and root boxes decoded as the
// shaders decode them, a face's geometry as they intersect it, and the sections' payload bytes.
#include "probebake/formats/trace_mesh.h"

#include <cmath>
#include <cstddef>

#include <glm/geometric.hpp>

#include "trace_box_decoding.h"

namespace probebake::formats {
namespace {

template <class Decode>
TraceBox child_box(const gpu::TraceTree& tree, const gpu::TraceNode& node, int child, Decode lower_of,
                   Decode upper_of) {
  const int shift = child == 0 ? 0 : 16;
  TraceBox box;
  for (int a = 0; a < 3; ++a) {
    box.lower[a] = lower_of(tree.lower[a], tree.scale[a], (node.lower[a] >> shift) & 0xFFFFu);
    box.upper[a] = upper_of(tree.lower[a], tree.scale[a], (node.upper[a] >> shift) & 0xFFFFu);
  }
  return box;
}

} // namespace

TraceBox decode_child_box(const gpu::TraceTree& tree, const gpu::TraceNode& node, int child) {
  return child_box(tree, node, child, decoded, decoded);
}

TraceBox narrowest_child_box(const gpu::TraceTree& tree, const gpu::TraceNode& node, int child) {
  return child_box(tree, node, child, highest_decoding, lowest_decoding);
}

TraceBox tree_box(const gpu::TraceTree& tree) {
  TraceBox box;
  box.lower = tree.lower;
  for (int a = 0; a < 3; ++a) box.upper[a] = decoded(tree.lower[a], tree.scale[a], gpu::TRACE_BOX_STEPS);
  return box;
}

std::size_t tracing_bytes(const ProbeVolume& v) {
  return v.bvh_nodes.size() * sizeof(gpu::BvhNode) + v.trace_triangles.size() * sizeof(gpu::TraceTriangle) +
         v.trace_trees.size() * sizeof(gpu::TraceTree) + v.trace_nodes.size() * sizeof(gpu::TraceNode) +
         v.trace_faces.size() * sizeof(gpu::TraceFace) + v.trace_vertices.size() * sizeof(gpu::TraceVertex) +
         v.trace_materials.size() * sizeof(gpu::TraceMaterial);
}

TraceFaceGeometry face_geometry(const ProbeVolume& volume, std::size_t face) {
  const gpu::TraceFace& f = volume.trace_faces[face];
  const auto corner = [&](int k) {
    const gpu::TraceVertex& p = volume.trace_vertices[f.vertex[k]];
    return glm::vec3(p.x, p.y, p.z);
  };
  TraceFaceGeometry g;
  g.v0 = corner(0);
  g.edge1 = corner(1) - g.v0;
  g.edge2 = corner(2) - g.v0;
  const glm::vec3 n = glm::cross(g.edge1, g.edge2);
  const float length = glm::length(n);
  if (length > 0.0f && std::isfinite(length)) g.normal = n / length;
  return g;
}

} // namespace probebake::formats
