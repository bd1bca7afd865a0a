// Validator phase for the compact tracing sections (format 1.4, trace_mesh.h): the trees the shaders walk
// without bounds checks of their own (trace_tree), the faces, vertices and materials they read
// (lighting_values, non_finite) and the dynamic objects' ranges in them (dynamic_ranges, dynamic_values).
//
// Boxes are checked exactly, without tolerance: a face must lie inside its leaf's box and every box above
// it, each decoded with the rounding that makes it smallest (a shader may or may not fuse the decoding's
// multiply-add), because that is the culling the GPU does.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "probebake/formats/trace_mesh.h"
#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

glm::vec3 vertex_at(const TracingView& t, std::uint32_t i) {
  const gpu::TraceVertex& p = t.vertices[i];
  return {p.x, p.y, p.z};
}

bool tree_finite(const gpu::TraceTree& t) { return finite3(t.lower) && finite3(t.scale) && finite3(tree_box(t).upper); }

bool material_finite(const gpu::TraceMaterial& m) { return finite3(m.albedo) && finite3(m.emission) && all_finite({m.pad0, m.pad1}); }

TraceBox intersect(const TraceBox& a, const TraceBox& b) { return {glm::max(a.lower, b.lower), glm::min(a.upper, b.upper)}; }

bool inside(const TraceBox& box, const glm::vec3& p) {
  return glm::all(glm::greaterThanEqual(p, box.lower)) && glm::all(glm::lessThanEqual(p, box.upper));
}

struct FaceRange {
  std::size_t begin = 0, end = 0;
};

// The faces of tree t: static faces before the first object's, then each object's range.
FaceRange tree_faces(const ProbeVolume& v, const TracingView& tracing, std::size_t t) {
  const auto& objects = v.dynamic_objects;
  if (t == 0) return {0, objects.empty() ? tracing.faces.size() : std::size_t(std::max(0, objects[0].first_triangle))};
  const gpu::DynamicObject& o = objects[t - 1];
  return {std::size_t(std::max(0, o.first_triangle)), std::size_t(std::max(0, o.first_triangle)) + std::size_t(std::max(0, o.triangle_count))};
}

// Walks every tree from its root: structure, depth, node and face ranges, boxes. Every node must be
// reached exactly once and every face lie in exactly one leaf of its own tree.
class TraceTreeChecker {
public:
  TraceTreeChecker(const ProbeVolume& v, const TracingView& t, Reporter& out)
      : v_(v), t_(t), out_(out), reached_(t.nodes.size(), 0), covered_(t.faces.size(), 0) {}

  void run() {
    std::size_t next_node = 0;
    for (std::size_t t = 0; t < v_.trace_trees.size(); ++t) {
      const gpu::TraceTree& tree = v_.trace_trees[t];
      if (!tree_finite(tree)) continue; // non_finite
      if (tree.scale.x < 0.0f || tree.scale.y < 0.0f || tree.scale.z < 0.0f) bad("trace_trees", t, "negative scale");
      const std::size_t nodes = std::size_t(std::max(0, tree.node_count));
      if (tree.node_count < 0) bad("trace_trees", t, "negative node_count");
      const FaceRange faces = tree_faces(v_, t_, t);
      if (faces.end > t_.faces.size() || faces.begin > faces.end) {
        bad("trace_trees", t, "its faces lie outside trace_faces");
        continue;
      }
      if (next_node + nodes > t_.nodes.size()) {
        bad("trace_trees", t, concat("its nodes [", next_node, ", ", next_node + nodes, ") lie outside trace_nodes"));
        return;
      }
      walk(t, next_node, nodes, faces);
      next_node += nodes;
    }
    if (next_node != t_.nodes.size()) out_.add("trace_tree", "trace_nodes", -1, concat("the trees hold ", next_node, " of ", t_.nodes.size(), " nodes"));
    for (std::size_t n = 0; n < reached_.size(); ++n)
      if (reached_[n] == 0) bad("trace_nodes", n, "not reachable from its tree's root");
    for (std::size_t f = 0; f < covered_.size(); ++f)
      if (covered_[f] == 0) bad("trace_faces", f, "in no leaf");
  }

private:
  struct Pending {
    std::uint32_t word;
    int depth;
    TraceBox box; // what the GPU tested on the way down: the intersection of every box above
  };

  void bad(const char* section, std::size_t index, const std::string& message) { out_.add("trace_tree", section, static_cast<long long>(index), message); }

  void walk(std::size_t t, std::size_t first_node, std::size_t node_count, FaceRange faces) {
    const gpu::TraceTree& tree = v_.trace_trees[t];
    if (tree.root == gpu::TRACE_NO_ROOT) {
      if (node_count != 0 || faces.end != faces.begin) bad("trace_trees", t, "no root but nodes or faces");
      return;
    }
    if (!is_leaf_word(tree.root) && tree.root != first_node) bad("trace_trees", t, concat("root ", tree.root, " is not its first node ", first_node));
    if (is_leaf_word(tree.root) && node_count != 0) bad("trace_trees", t, "a leaf root with nodes");
    std::vector<Pending> stack{{tree.root, 0, tree_box(tree)}};
    while (!stack.empty()) {
      const Pending p = stack.back();
      stack.pop_back();
      if (is_leaf_word(p.word)) leaf(p, faces);
      else inner(t, p, first_node, first_node + node_count, stack);
    }
  }

  void inner(std::size_t t, const Pending& p, std::size_t begin, std::size_t end, std::vector<Pending>& stack) {
    const std::size_t n = p.word;
    if (n < begin || n >= end) return bad("trace_trees", t, concat("node ", n, " outside the tree's nodes [", begin, ", ", end, ")"));
    if (reached_[n]++ != 0) return bad("trace_nodes", n, "reached twice");
    if (p.depth >= gpu::BVH_MAX_DEPTH) return bad("trace_nodes", n, concat("depth ", p.depth, " reaches BVH_MAX_DEPTH"));
    const gpu::TraceNode& node = t_.nodes[n];
    for (int c = 0; c < 2; ++c) {
      const std::uint32_t child = node.child[c];
      if (!is_leaf_word(child) && child <= n) {
        bad("trace_nodes", n, concat("child ", child, " is not after the node"));
        continue;
      }
      stack.push_back({child, p.depth + 1, intersect(p.box, narrowest_child_box(v_.trace_trees[t], node, c))});
    }
  }

  void leaf(const Pending& p, FaceRange faces) {
    const std::size_t first = leaf_first(p.word), count = leaf_count(p.word);
    if (count > std::size_t(gpu::TRACE_MAX_LEAF_FACES) || first < faces.begin || first + count > faces.end)
      return bad("trace_faces", first, concat("a leaf of ", count, " faces at ", first, " outside its tree's faces [", faces.begin, ", ", faces.end, ")"));
    for (std::size_t f = first; f < first + count; ++f) {
      if (covered_[f]++ != 0) bad("trace_faces", f, "in two leaves");
      for (std::uint32_t k : t_.faces[f].vertex)
        if (k < t_.vertices.size() && !inside(p.box, vertex_at(t_, k))) bad("trace_faces", f, concat("vertex ", k, " outside a box above it"));
    }
  }

  const ProbeVolume& v_;
  const TracingView& t_;
  Reporter& out_;
  std::vector<std::uint8_t> reached_, covered_;
};

std::string face_problem(const ProbeVolume& v, const TracingView& t, const gpu::TraceFace& face) {
  for (std::uint32_t k : face.vertex)
    if (k >= t.vertices.size()) return concat("vertex ", k, " outside trace_vertices");
  if ((face.material & gpu::TRACE_MATERIAL_MASK) >= v.trace_materials.size()) return concat("material ", face.material & gpu::TRACE_MATERIAL_MASK, " outside trace_materials");
  const glm::vec3 v0 = vertex_at(t, face.vertex[0]);
  const float area = glm::length(glm::cross(vertex_at(t, face.vertex[1]) - v0, vertex_at(t, face.vertex[2]) - v0));
  if (!(area > 0.0f) || !std::isfinite(area)) return "zero or infinite area (such triangles are left out)";
  return "";
}

std::string material_problem(const gpu::TraceMaterial& m) {
  if (negative(m.albedo) || negative(m.emission)) return "negative albedo or emission";
  if (!zero_bits({m.pad0, m.pad1})) return "padding is not zero";
  return "";
}

void check_values(const ProbeVolume& v, const TracingView& t, Reporter& out) {
  for (std::size_t i = 0; i < t.vertices.size(); ++i)
    if (!all_finite({t.vertices[i].x, t.vertices[i].y, t.vertices[i].z})) out.add("non_finite", "trace_vertices", (long long)i, "a float is NaN or infinite");
  for (std::size_t i = 0; i < v.trace_trees.size(); ++i)
    if (!tree_finite(v.trace_trees[i])) out.add("non_finite", "trace_trees", (long long)i, "a float is NaN or infinite (or its box's upper corner is)");
  for (std::size_t i = 0; i < v.trace_materials.size(); ++i) {
    const gpu::TraceMaterial& m = v.trace_materials[i];
    if (!material_finite(m)) out.add("non_finite", "trace_materials", (long long)i, "a float is NaN or infinite");
    else if (const std::string problem = material_problem(m); !problem.empty()) out.add("lighting_values", "trace_materials", (long long)i, problem);
  }
  for (std::size_t i = 0; i < t.faces.size(); ++i)
    if (const std::string problem = face_problem(v, t, t.faces[i]); !problem.empty()) out.add("lighting_values", "trace_faces", (long long)i, problem);
}

// Objects' faces follow the static ones in object order; bvh_root is the object's tree (1 + o) and
// bvh_node_count its node count.
void check_object_ranges(const ProbeVolume& v, const TracingView& t, Reporter& out) {
  std::size_t next_face = v.dynamic_objects.empty() ? t.faces.size() : std::size_t(std::max(0, v.dynamic_objects[0].first_triangle));
  for (std::size_t o = 0; o < v.dynamic_objects.size(); ++o) {
    const gpu::DynamicObject& object = v.dynamic_objects[o];
    const auto bad = [&](const std::string& message) { out.add("dynamic_ranges", "dynamic_objects", (long long)o, message); };
    if (object.triangle_count < 1) bad("an object has no face");
    if (object.first_triangle < 0 || std::size_t(object.first_triangle) != next_face) bad(concat("first_triangle ", object.first_triangle, " does not follow the previous faces at ", next_face));
    next_face = std::size_t(std::max(0, object.first_triangle)) + std::size_t(std::max(0, object.triangle_count));
    if (object.bvh_root != int(o) + 1) bad(concat("bvh_root ", object.bvh_root, " is not its tree ", o + 1));
    else if (object.bvh_node_count != v.trace_trees[o + 1].node_count) bad("bvh_node_count is not its tree's");
  }
  if (next_face != t.faces.size()) out.add("dynamic_ranges", "trace_faces", -1, concat("objects end at face ", next_face, " of ", t.faces.size()));
}

// Every vertex of an object's faces lies in the object's box (the runtime refits world boxes from it).
void check_object_boxes(const ProbeVolume& v, const TracingView& t, Reporter& out) {
  for (std::size_t o = 0; o < v.dynamic_objects.size(); ++o) {
    const gpu::DynamicObject& object = v.dynamic_objects[o];
    const auto outside = [&](std::size_t f) {
      for (std::uint32_t k : t.faces[f].vertex) {
        const glm::vec3 p = vertex_at(t, k);
        if (glm::any(glm::lessThan(p, object.lower)) || glm::any(glm::greaterThan(p, object.upper))) return true;
      }
      return false;
    };
    const std::size_t first = std::size_t(object.first_triangle), end = first + std::size_t(object.triangle_count); // checked ranges
    for (std::size_t f = first; f < end; ++f) {
      if (!outside(f)) continue;
      out.add("dynamic_values", "dynamic_objects", (long long)o, concat("face ", f, " lies outside the object's box"));
      break;
    }
  }
}

} // namespace

bool uses_compact_tracing(const ProbeVolume& v, const TracingView& t) {
  return !v.trace_trees.empty() || !t.nodes.empty() || !t.faces.empty() || !t.vertices.empty() || !v.trace_materials.empty();
}

void check_trace_mesh(const ProbeVolume& v, const TracingView& t, Reporter& out) {
  if (has_float_tracing(v)) return out.add("lighting_sections", "trace_trees", -1, "both the float (1.1-1.3) and the compact (1.4) tracing sections");
  const std::size_t expected_trees = 1 + v.dynamic_objects.size();
  if (v.trace_trees.size() != expected_trees) return out.add("lighting_sections", "trace_trees", -1, concat(v.trace_trees.size(), " trees, expected 1 + dynamic objects = ", expected_trees));
  const std::size_t reported = out.count();
  check_values(v, t, out);
  check_object_ranges(v, t, out);
  if (out.count() != reported) return; // the boxes and the walk below index with these
  check_object_boxes(v, t, out);
  TraceTreeChecker(v, t, out).run();
}

} // namespace probebake::formats::detail
