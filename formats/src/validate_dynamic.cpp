// Validator phase for the dynamic objects (format 1.3, docs/FORMAT.md "Dynamic objects"): each object's BVH
// nodes and triangles are a contiguous range after the static ones and its tree stays inside them (the
// runtime traverses an object from bvh_root with absolute indices); its box holds its triangles; its rest
// pose is a finite affine transform that keeps orientation (the runtime turns object normals into world
// normals with the inverse transpose, which a mirror would turn inside out).
#include <algorithm>
#include <cmath>
#include <cstddef>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

constexpr float kObjectBoxTolerance = 1e-5f; // containment, relative to the box's largest coordinate

bool object_finite(const gpu::DynamicObject& o) {
  bool finite = finite3(o.lower) && finite3(o.upper);
  for (const glm::vec4& row : o.rest_rows) finite = finite && all_finite({row.x, row.y, row.z, row.w});
  return finite;
}

float rest_determinant(const gpu::DynamicObject& o) {
  const glm::vec3 a(o.rest_rows[0]), b(o.rest_rows[1]), c(o.rest_rows[2]);
  return glm::dot(a, glm::cross(b, c));
}

// Node and triangle ranges of the static part and of each object: [begin, end) pairs.
struct Range {
  std::size_t begin = 0, end = 0;
  bool holds(std::size_t i) const { return i >= begin && i < end; }
};

void check_ranges(const ProbeVolume& v, Reporter& out) {
  const auto& objects = v.dynamic_objects;
  std::size_t next_node = std::size_t(std::max(0, objects[0].bvh_root));
  std::size_t next_triangle = std::size_t(std::max(0, objects[0].first_triangle));
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const gpu::DynamicObject& o = objects[i];
    const auto bad = [&](const std::string& message) {
      out.add("dynamic_ranges", "dynamic_objects", static_cast<long long>(i), message);
    };
    if (o.bvh_node_count < 1 || o.triangle_count < 1) bad("an object has no BVH node or no triangle");
    if (o.bvh_root < 0 || std::size_t(o.bvh_root) != next_node)
      bad(concat("bvh_root ", o.bvh_root, " does not follow the previous nodes at ", next_node));
    if (o.first_triangle < 0 || std::size_t(o.first_triangle) != next_triangle)
      bad(concat("first_triangle ", o.first_triangle, " does not follow the previous triangles at ", next_triangle));
    next_node = std::size_t(std::max(0, o.bvh_root)) + std::size_t(std::max(0, o.bvh_node_count));
    next_triangle = std::size_t(std::max(0, o.first_triangle)) + std::size_t(std::max(0, o.triangle_count));
    if (o.gltf_node < 0) bad(concat("gltf_node ", o.gltf_node, " is negative"));
    if (o.pad0 != 0) bad("padding is not zero");
  }
  if (next_node != v.bvh_nodes.size())
    out.add("dynamic_ranges", "bvh_nodes", -1, concat("objects end at node ", next_node, " of ", v.bvh_nodes.size()));
  if (next_triangle != v.trace_triangles.size())
    out.add("dynamic_ranges", "trace_triangles", -1,
            concat("objects end at triangle ", next_triangle, " of ", v.trace_triangles.size()));
}

// Every node of a range points only inside its range (children) and its triangle range (leaves).
void check_tree_inside(const ProbeVolume& v, Range nodes, Range triangles, long long object, Reporter& out) {
  for (std::size_t n = nodes.begin; n < nodes.end && n < v.bvh_nodes.size(); ++n) {
    const gpu::BvhNode& node = v.bvh_nodes[n];
    const bool inside =
        node.count == 0
            ? node.first >= 0 && nodes.holds(std::size_t(node.first)) && nodes.holds(std::size_t(node.first) + 1)
            : node.first >= 0 && node.count > 0 && triangles.holds(std::size_t(node.first)) &&
                  triangles.holds(std::size_t(node.first) + std::size_t(node.count) - 1);
    if (!inside)
      out.add("dynamic_ranges", "bvh_nodes", static_cast<long long>(n),
              object < 0 ? std::string("a static node points outside the static ranges")
                         : concat("a node of object ", object, " points outside its ranges"));
  }
}

void check_object_values(const ProbeVolume& v, std::size_t i, Reporter& out) {
  const gpu::DynamicObject& o = v.dynamic_objects[i];
  const auto bad = [&](const std::string& message) {
    out.add("dynamic_values", "dynamic_objects", static_cast<long long>(i), message);
  };
  if (!object_finite(o)) return bad("a float is NaN or infinite");
  if (!(rest_determinant(o) > 1e-12f)) bad("rest pose is singular or mirrored (determinant <= 0)");
  if (o.lower.x > o.upper.x || o.lower.y > o.upper.y || o.lower.z > o.upper.z) return bad("box lower > upper");
  const glm::vec3 magnitude = glm::max(glm::abs(o.lower), glm::abs(o.upper));
  const float slack = kObjectBoxTolerance * std::max({magnitude.x, magnitude.y, magnitude.z, 1e-30f});
  const std::size_t end =
      std::min(v.trace_triangles.size(), std::size_t(o.first_triangle) + std::size_t(o.triangle_count));
  for (std::size_t t = std::size_t(o.first_triangle); t < end; ++t) {
    const gpu::TraceTriangle& tri = v.trace_triangles[t];
    for (const glm::vec3& p : {tri.v0, tri.v0 + tri.edge1, tri.v0 + tri.edge2}) {
      if (glm::any(glm::lessThan(p, o.lower - slack)) || glm::any(glm::greaterThan(p, o.upper + slack)))
        return bad(concat("triangle ", t, " lies outside the object's box"));
    }
  }
}

} // namespace

void check_dynamic_objects(const ProbeVolume& v, const TracingView& tracing, Reporter& out) {
  if (v.dynamic_objects.empty()) return;
  if (!v.lighting)
    return out.add("lighting_sections", "dynamic_objects", -1, "dynamic objects without a lighting_info section");
  if (v.lighting->dynamic_objects != static_cast<long long>(v.dynamic_objects.size())) {
    out.add("lighting_sections", "dynamic_objects", -1,
            concat("dynamic_objects is ", v.lighting->dynamic_objects, " but the section has ",
                   v.dynamic_objects.size(), " elements"));
  }
  if (uses_compact_tracing(v,
                           tracing)) { // format 1.4: ranges and boxes are checked with the trees (validate_tracing.cpp)
    for (std::size_t i = 0; i < v.dynamic_objects.size(); ++i) check_object_values(v, i, out);
    return;
  }
  const std::size_t reported = out.count();
  check_ranges(v, out);
  if (out.count() != reported) return; // the trees and boxes below index with these ranges
  const auto& objects = v.dynamic_objects;
  check_tree_inside(v, {0, std::size_t(objects[0].bvh_root)}, {0, std::size_t(objects[0].first_triangle)}, -1, out);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const gpu::DynamicObject& o = objects[i];
    check_tree_inside(v, {std::size_t(o.bvh_root), std::size_t(o.bvh_root + o.bvh_node_count)},
                      {std::size_t(o.first_triangle), std::size_t(o.first_triangle + o.triangle_count)},
                      static_cast<long long>(i), out);
    check_object_values(v, i, out);
  }
}

} // namespace probebake::formats::detail
