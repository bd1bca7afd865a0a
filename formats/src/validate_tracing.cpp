// Validator phase for the compact tracing sections (format 1.4, trace_mesh.h): the trees the shaders walk
// without bounds checks of their own (trace_tree), the faces, vertices and materials they read
// (lighting_values, non_finite) and the dynamic objects' ranges in them (dynamic_ranges, dynamic_values).
//
// validate_without_cells leaves the cells' own ranges unread (holes): the walk of the static tree stops where
// it enters a cell and records the entry, from which check_cell_trace_mesh walks the cell when it arrives.
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
#include "tracing_holes.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

bool tree_finite(const gpu::TraceTree& t) { return finite3(t.lower) && finite3(t.scale) && finite3(tree_box(t).upper); }

bool material_finite(const gpu::TraceMaterial& m) {
  return finite3(m.albedo) && finite3(m.emission) && all_finite({m.pad0, m.pad1});
}

glm::vec3 position(const gpu::TraceVertex& p) { return {p.x, p.y, p.z}; }

TraceBox intersect(const TraceBox& a, const TraceBox& b) {
  return {glm::max(a.lower, b.lower), glm::min(a.upper, b.upper)};
}

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
  return {std::size_t(std::max(0, o.first_triangle)),
          std::size_t(std::max(0, o.first_triangle)) + std::size_t(std::max(0, o.triangle_count))};
}

// Walks trees from their roots: structure, depth, node and face ranges, boxes. Every node must be reached
// exactly once and every face lie in exactly one leaf of its own tree. Indices are the file's; the window
// holds the elements read. Without the cells (`deferred`), the static tree's walk stops at each cell's entry.
class TraceTreeChecker {
public:
  TraceTreeChecker(const ProbeVolume& v, const Readable& r, const DeferredCells* deferred, Reporter& out)
      : v_(v),
        w_(r.window),
        r_(r),
        deferred_(deferred),
        out_(out),
        reached_(w_.view.nodes.size(), r.nodes),
        covered_(w_.view.faces.size(), r.faces) {}

  void run() {
    std::size_t next_node = 0;
    for (std::size_t t = 0; t < v_.trace_trees.size(); ++t) {
      const gpu::TraceTree& tree = v_.trace_trees[t];
      if (!tree_finite(tree)) continue; // non_finite
      if (tree.scale.x < 0.0f || tree.scale.y < 0.0f || tree.scale.z < 0.0f) bad("trace_trees", t, "negative scale");
      const std::size_t nodes = std::size_t(std::max(0, tree.node_count));
      if (tree.node_count < 0) bad("trace_trees", t, "negative node_count");
      const FaceRange faces = tree_faces(v_, w_.view, t);
      if (faces.end > w_.view.faces.size() || faces.begin > faces.end) {
        bad("trace_trees", t, "its faces lie outside trace_faces");
        continue;
      }
      if (next_node + nodes > w_.view.nodes.size()) {
        bad("trace_trees", t, concat("its nodes [", next_node, ", ", next_node + nodes, ") lie outside trace_nodes"));
        return;
      }
      walk(t, next_node, nodes, faces);
      next_node += nodes;
    }
    if (next_node != w_.view.nodes.size())
      out_.add("trace_tree", "trace_nodes", -1,
               concat("the trees hold ", next_node, " of ", w_.view.nodes.size(), " nodes"));
    finish();
  }

  // Cell record k alone (the window holds its ranges), from where the static tree enters it.
  void run_cell(std::size_t k, const CellEntry& entry) {
    const CellTracing& r = v_.cell_tracing[k];
    if (!entry.reached) {
      if (r.trace_nodes.count + r.trace_faces.count > 0)
        out_.add("trace_tree", "cell_tracing", (long long)k, "the static tree does not reach the cell");
      return;
    }
    first_node_ = r.trace_nodes.first, end_node_ = first_node_ + r.trace_nodes.count;
    descend(0, {{entry.word, entry.depth, entry.box}},
            {r.trace_faces.first, std::size_t(r.trace_faces.first) + r.trace_faces.count});
    finish();
  }

private:
  struct Pending {
    std::uint32_t word;
    int depth;
    TraceBox box; // what the GPU tested on the way down: the intersection of every box above
  };

  void bad(const char* section, std::size_t index, const std::string& message) {
    out_.add("trace_tree", section, static_cast<long long>(index), message);
  }

  void finish() {
    reached_.for_each_zero(w_.node_base,
                           [&](std::uint64_t n) { bad("trace_nodes", n, "not reachable from its tree's root"); });
    covered_.for_each_zero(w_.face_base, [&](std::uint64_t f) { bad("trace_faces", f, "in no leaf"); });
    if (!deferred_) return;
    for (std::size_t k = 0; k < v_.cell_tracing.size(); ++k) {
      const CellTracing& r = v_.cell_tracing[k];
      if (!deferred_->entries[k].reached && r.trace_nodes.count + r.trace_faces.count > 0)
        out_.add("trace_tree", "cell_tracing", (long long)k, "the static tree's top level does not reach the cell");
    }
  }

  void walk(std::size_t t, std::size_t first_node, std::size_t node_count, FaceRange faces) {
    const gpu::TraceTree& tree = v_.trace_trees[t];
    if (tree.root == gpu::TRACE_NO_ROOT) {
      if (node_count != 0 || faces.end != faces.begin) bad("trace_trees", t, "no root but nodes or faces");
      return;
    }
    if (!is_leaf_word(tree.root) && tree.root != first_node)
      bad("trace_trees", t, concat("root ", tree.root, " is not its first node ", first_node));
    if (is_leaf_word(tree.root) && node_count != 0) bad("trace_trees", t, "a leaf root with nodes");
    first_node_ = first_node, end_node_ = first_node + node_count;
    descend(t, {{tree.root, 0, tree_box(tree)}}, faces);
  }

  void descend(std::size_t t, std::vector<Pending> stack, FaceRange faces) {
    while (!stack.empty()) {
      const Pending p = stack.back();
      stack.pop_back();
      if (t == 0 && enters_cell(p)) continue;
      if (is_leaf_word(p.word))
        leaf(p, faces);
      else
        inner(t, p, stack);
    }
  }

  // Without the cells: a word of the static tree that leads into a cell's range must be the cell's entry
  // (its first node, or the one leaf of a cell without nodes); it is recorded, not followed.
  bool enters_cell(const Pending& p) {
    if (!deferred_) return false;
    const bool leaf = is_leaf_word(p.word);
    const Hole* hole = leaf ? hole_at(r_.faces, leaf_first(p.word)) : hole_at(r_.nodes, p.word);
    if (leaf && !hole) hole = hole_at(r_.faces, std::uint64_t(leaf_first(p.word)) + leaf_count(p.word) - 1);
    if (!hole) return false;
    const std::size_t k = hole->cell;
    const CellTracing& r = v_.cell_tracing[k];
    const bool exact = leaf ? r.trace_nodes.count == 0 && leaf_first(p.word) == r.trace_faces.first &&
                                  leaf_count(p.word) == r.trace_faces.count
                            : p.word == r.trace_nodes.first;
    if (!exact)
      bad(leaf ? "trace_faces" : "trace_nodes", leaf ? leaf_first(p.word) : p.word,
          concat("the static tree enters cell record ", k, " elsewhere than at its root"));
    else if (deferred_->entries[k].reached)
      bad("trace_nodes", p.word, concat("the static tree enters cell record ", k, " twice"));
    else
      deferred_->entries[k] = {p.word, p.depth, p.box, true};
    return true;
  }

  void inner(std::size_t t, const Pending& p, std::vector<Pending>& stack) {
    const std::size_t n = p.word;
    if (n < first_node_ || n >= end_node_ || !w_.has_node(n))
      return bad("trace_trees", t,
                 concat("node ", n, " outside the tree's nodes [", first_node_, ", ", end_node_, ")"));
    if (reached_.at(n - w_.node_base)++ != 0) return bad("trace_nodes", n, "reached twice");
    if (p.depth >= gpu::BVH_MAX_DEPTH)
      return bad("trace_nodes", n, concat("depth ", p.depth, " reaches BVH_MAX_DEPTH"));
    const gpu::TraceNode& node = w_.node(n);
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
    if (count > std::size_t(gpu::TRACE_MAX_LEAF_FACES) || first < faces.begin || first + count > faces.end ||
        !w_.has_face(first) || !w_.has_face(first + count - 1))
      return bad("trace_faces", first,
                 concat("a leaf of ", count, " faces at ", first, " outside its tree's faces [", faces.begin, ", ",
                        faces.end, ")"));
    for (std::size_t f = first; f < first + count; ++f)
      if (hole_at(r_.faces, f - w_.face_base))
        return bad("trace_faces", first,
                   concat("a leaf of ", count, " faces at ", first, " reaches into a cell's faces"));
    for (std::size_t f = first; f < first + count; ++f) {
      if (covered_.at(f - w_.face_base)++ != 0) bad("trace_faces", f, "in two leaves");
      for (std::uint32_t k : w_.face(f).vertex)
        if (w_.has_vertex(k) && !hole_at(r_.vertices, k - w_.vertex_base) && !inside(p.box, position(w_.vertex(k))))
          bad("trace_faces", f, concat("vertex ", k, " outside a box above it"));
    }
  }

  const ProbeVolume& v_;
  const TracingWindow& w_;
  const Readable& r_;
  const DeferredCells* deferred_;
  Reporter& out_;
  Marks reached_, covered_;
  std::size_t first_node_ = 0, end_node_ = 0; // the nodes of the tree being walked
};

std::string face_problem(const ProbeVolume& v, const TracingWindow& w, const gpu::TraceFace& face) {
  for (std::uint32_t k : face.vertex)
    if (!w.has_vertex(k)) return concat("vertex ", k, " outside trace_vertices");
  if ((face.material & gpu::TRACE_MATERIAL_MASK) >= v.trace_materials.size())
    return concat("material ", face.material & gpu::TRACE_MATERIAL_MASK, " outside trace_materials");
  const glm::vec3 v0 = position(w.vertex(face.vertex[0]));
  const float area =
      glm::length(glm::cross(position(w.vertex(face.vertex[1])) - v0, position(w.vertex(face.vertex[2])) - v0));
  if (!(area > 0.0f) || !std::isfinite(area)) return "zero or infinite area (such triangles are left out)";
  return "";
}

std::string material_problem(const gpu::TraceMaterial& m) {
  if (negative(m.albedo) || negative(m.emission)) return "negative albedo or emission";
  if (!zero_bits({m.pad0, m.pad1})) return "padding is not zero";
  return "";
}

void check_tables(const ProbeVolume& v, Reporter& out) {
  for (std::size_t i = 0; i < v.trace_trees.size(); ++i)
    if (!tree_finite(v.trace_trees[i]))
      out.add("non_finite", "trace_trees", (long long)i, "a float is NaN or infinite (or its box's upper corner is)");
  for (std::size_t i = 0; i < v.trace_materials.size(); ++i) {
    const gpu::TraceMaterial& m = v.trace_materials[i];
    if (!material_finite(m))
      out.add("non_finite", "trace_materials", (long long)i, "a float is NaN or infinite");
    else if (const std::string problem = material_problem(m); !problem.empty())
      out.add("lighting_values", "trace_materials", (long long)i, problem);
  }
}

// The readable vertices and faces. A face of the global part whose vertex lies in a cell reads a hole here
// (zeros); check_cells reports such a face.
void check_values(const ProbeVolume& v, const Readable& r, Reporter& out) {
  const TracingWindow& w = r.window;
  for_each_outside(r.vertices, w.view.vertices.size(), [&](std::uint64_t i) {
    const gpu::TraceVertex& p = w.view.vertices[i];
    if (!all_finite({p.x, p.y, p.z}))
      out.add("non_finite", "trace_vertices", (long long)(w.vertex_base + i), "a float is NaN or infinite");
  });
  for_each_outside(r.faces, w.view.faces.size(), [&](std::uint64_t i) {
    if (const std::string problem = face_problem(v, w, w.view.faces[i]); !problem.empty())
      out.add("lighting_values", "trace_faces", (long long)(w.face_base + i), problem);
  });
}

// Objects' faces follow the static ones in object order; bvh_root is the object's tree (1 + o) and
// bvh_node_count its node count.
void check_object_ranges(const ProbeVolume& v, const TracingView& t, Reporter& out) {
  std::size_t next_face =
      v.dynamic_objects.empty() ? t.faces.size() : std::size_t(std::max(0, v.dynamic_objects[0].first_triangle));
  for (std::size_t o = 0; o < v.dynamic_objects.size(); ++o) {
    const gpu::DynamicObject& object = v.dynamic_objects[o];
    const auto bad = [&](const std::string& message) {
      out.add("dynamic_ranges", "dynamic_objects", (long long)o, message);
    };
    if (object.triangle_count < 1) bad("an object has no face");
    if (object.first_triangle < 0 || std::size_t(object.first_triangle) != next_face)
      bad(concat("first_triangle ", object.first_triangle, " does not follow the previous faces at ", next_face));
    next_face = std::size_t(std::max(0, object.first_triangle)) + std::size_t(std::max(0, object.triangle_count));
    if (object.bvh_root != int(o) + 1)
      bad(concat("bvh_root ", object.bvh_root, " is not its tree ", o + 1));
    else if (object.bvh_node_count != v.trace_trees[o + 1].node_count)
      bad("bvh_node_count is not its tree's");
  }
  if (next_face != t.faces.size())
    out.add("dynamic_ranges", "trace_faces", -1, concat("objects end at face ", next_face, " of ", t.faces.size()));
}

// Every vertex of an object's faces lies in the object's box (the runtime refits world boxes from it). A
// vertex in a cell is not read (check_cells reports the face).
void check_object_boxes(const ProbeVolume& v, const Readable& r, Reporter& out) {
  const TracingView& t = r.window.view;
  for (std::size_t o = 0; o < v.dynamic_objects.size(); ++o) {
    const gpu::DynamicObject& object = v.dynamic_objects[o];
    const auto outside = [&](std::size_t f) {
      for (std::uint32_t k : t.faces[f].vertex) {
        if (hole_at(r.vertices, k)) continue;
        const glm::vec3 p = position(t.vertices[k]);
        if (glm::any(glm::lessThan(p, object.lower)) || glm::any(glm::greaterThan(p, object.upper))) return true;
      }
      return false;
    };
    const std::size_t first = std::size_t(object.first_triangle),
                      end = first + std::size_t(object.triangle_count); // checked ranges
    for (std::size_t f = first; f < end; ++f) {
      if (!outside(f)) continue;
      out.add("dynamic_values", "dynamic_objects", (long long)o, concat("face ", f, " lies outside the object's box"));
      break;
    }
  }
}

} // namespace

bool uses_compact_tracing(const ProbeVolume& v, const TracingView& t) {
  return !v.trace_trees.empty() || !t.nodes.empty() || !t.faces.empty() || !t.vertices.empty() ||
         !v.trace_materials.empty();
}

void check_trace_mesh(const ProbeVolume& v, const TracingView& t, const DeferredCells* deferred, Reporter& out) {
  if (has_float_tracing(v))
    return out.add("lighting_sections", "trace_trees", -1,
                   "both the float (1.1-1.3) and the compact (1.4) tracing sections");
  const std::size_t expected_trees = 1 + v.dynamic_objects.size();
  if (v.trace_trees.size() != expected_trees)
    return out.add("lighting_sections", "trace_trees", -1,
                   concat(v.trace_trees.size(), " trees, expected 1 + dynamic objects = ", expected_trees));
  const std::size_t reported = out.count();
  const TracingWindow whole{t};
  const Readable r = readable(v, whole, deferred);
  check_tables(v, out);
  check_values(v, r, out);
  check_object_ranges(v, t, out);
  if (out.count() != reported) return; // the boxes and the walk below index with these
  check_object_boxes(v, r, out);
  TraceTreeChecker(v, r, deferred, out).run();
}

void check_cell_trace_mesh(const ProbeVolume& v, const CellEntry& entry, std::size_t k, const TracingWindow& cell,
                           Reporter& out) {
  const std::size_t reported = out.count();
  const Readable r{cell, {}, {}, {}};
  check_values(v, r, out);
  if (out.count() != reported) return; // the walk reads the faces' vertices
  TraceTreeChecker(v, r, nullptr, out).run_cell(k, entry);
}

} // namespace probebake::formats::detail
