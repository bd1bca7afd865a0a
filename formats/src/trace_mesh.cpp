// Compact tracing sections (trace_mesh.h): building them and upgrading a 1.1-1.3 volume to them (reading
// them back is in trace_mesh_read.cpp). The one subtle part is the box quantisation: a shader decodes
// q as lower + q * scale, which a compiler may fuse into one fma, so every quantised bound is checked
// against both roundings and stepped outwards until neither can cut into the exact box, then one more
// step for devices that flush denormals.
#include "probebake/formats/trace_mesh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include <glm/common.hpp>

#include "probebake/formats/error.h"
#include "trace_box_decoding.h"

namespace probebake::formats {
namespace {

constexpr float kSteps = float(gpu::TRACE_BOX_STEPS);

// The step of one axis: the smallest float with lower + TRACE_BOX_STEPS * step >= upper in both roundings.
float frame_step(float lower, float upper) {
  if (!(upper > lower)) return 0.0f;
  float step = (upper - lower) / kSteps;
  while (lowest_decoding(lower, step, gpu::TRACE_BOX_STEPS) < upper)
    step = std::nextafter(step, std::numeric_limits<float>::infinity());
  return step;
}

std::uint32_t quantise_lower(float x, float lower, float scale) {
  if (scale == 0.0f) return 0;
  double q = std::floor((double(x) - double(lower)) / double(scale));
  auto qi = std::uint32_t(std::clamp(q, 0.0, double(gpu::TRACE_BOX_STEPS)));
  while (qi > 0 && highest_decoding(lower, scale, qi) > x) --qi;
  return qi > 0 ? qi - 1 : 0;
}

std::uint32_t quantise_upper(float x, float lower, float scale) {
  if (scale == 0.0f) return 0;
  double q = std::ceil((double(x) - double(lower)) / double(scale));
  auto qi = std::uint32_t(std::clamp(q, 0.0, double(gpu::TRACE_BOX_STEPS)));
  while (qi < gpu::TRACE_BOX_STEPS && lowest_decoding(lower, scale, qi) < x) ++qi;
  return qi < gpu::TRACE_BOX_STEPS ? qi + 1 : qi;
}

struct Box {
  glm::vec3 lower{std::numeric_limits<float>::max()};
  glm::vec3 upper{-std::numeric_limits<float>::max()};
  void grow(const glm::vec3& p) { lower = glm::min(lower, p), upper = glm::max(upper, p); }
  void grow(const Box& b) { lower = glm::min(lower, b.lower), upper = glm::max(upper, b.upper); }
};

std::uint64_t hash_bits(const float* values, int n) {
  std::uint64_t h = 1469598103934665603ull; // FNV-1a over the float bits
  for (int i = 0; i < n; ++i) {
    const auto bits = std::bit_cast<std::uint32_t>(values[i]);
    for (int b = 0; b < 4; ++b) h = (h ^ ((bits >> (8 * b)) & 0xFFu)) * 1099511628211ull;
  }
  return h;
}

bool same_bits(const float* a, const float* b, int n) { return std::memcmp(a, b, sizeof(float) * std::size_t(n)) == 0; }

[[noreturn]] void malformed(const std::string& reason) { throw Error(ErrorKind::internal, "trace mesh: " + reason); }

// Exact boxes of every input node, children before parents (children have larger indices).
std::vector<Box> node_boxes(const TraceTreeInput& tree) {
  std::vector<Box> boxes(tree.nodes.size());
  for (std::size_t n = tree.nodes.size(); n-- > 0;) {
    const gpu::BvhNode& node = tree.nodes[n];
    if (node.count > 0) {
      if (node.count > gpu::TRACE_MAX_LEAF_FACES || node.first < 0 ||
          std::size_t(node.first) + std::size_t(node.count) > tree.triangles.size())
        malformed("leaf " + std::to_string(n) + " is out of range");
      for (int k = node.first; k < node.first + node.count; ++k)
        for (const glm::vec3& p : tree.triangles[std::size_t(k)].corners) boxes[n].grow(p);
      continue;
    }
    if (node.first <= int(n) || std::size_t(node.first) + 1 >= tree.nodes.size())
      malformed("inner node " + std::to_string(n) + " has bad children");
    boxes[n].grow(boxes[std::size_t(node.first)]);
    boxes[n].grow(boxes[std::size_t(node.first) + 1]);
  }
  return boxes;
}

gpu::TraceTree tree_frame(const Box& root) {
  gpu::TraceTree tree{};
  tree.lower = root.lower;
  for (int a = 0; a < 3; ++a) tree.scale[a] = frame_step(root.lower[a], root.upper[a]);
  return tree;
}

void set_child_box(gpu::TraceNode& node, int child, const gpu::TraceTree& frame, const Box& box) {
  const int shift = child == 0 ? 0 : 16;
  for (int a = 0; a < 3; ++a) {
    node.lower[a] |= quantise_lower(box.lower[a], frame.lower[a], frame.scale[a]) << shift;
    node.upper[a] |= quantise_upper(box.upper[a], frame.lower[a], frame.scale[a]) << shift;
  }
}

// Appends the tree's inner nodes (children after parents, as in the input) with faces numbered from
// face_base; returns the root's child word.
std::uint32_t append_inner_nodes(std::vector<gpu::TraceNode>& nodes, const TraceTreeInput& tree,
                                 const std::vector<Box>& boxes, const gpu::TraceTree& frame, std::size_t face_base) {
  const std::size_t node_base = nodes.size();
  // Inner input nodes become compact nodes in index order, so children keep larger indices than parents.
  std::vector<std::uint32_t> compact(tree.nodes.size(), 0);
  std::uint32_t inner = 0;
  for (std::size_t n = 0; n < tree.nodes.size(); ++n)
    if (tree.nodes[n].count == 0) compact[n] = std::uint32_t(node_base) + inner++;
  const auto word = [&](std::size_t n) {
    const gpu::BvhNode& node = tree.nodes[n];
    if (node.count == 0) return compact[n];
    return gpu::TRACE_CHILD_LEAF | (std::uint32_t(node.count - 1) << gpu::TRACE_LEAF_COUNT_SHIFT) |
           std::uint32_t(face_base + std::size_t(node.first));
  };
  for (std::size_t n = 0; n < tree.nodes.size(); ++n) {
    if (tree.nodes[n].count != 0) continue;
    gpu::TraceNode node{};
    for (int c = 0; c < 2; ++c) {
      const std::size_t child = std::size_t(tree.nodes[n].first) + std::size_t(c);
      set_child_box(node, c, frame, boxes[child]);
      node.child[c] = word(child);
    }
    nodes.push_back(node);
  }
  if (nodes.size() > std::size_t(gpu::TRACE_LEAF_FIRST_MASK)) malformed("more nodes than a child word holds");
  return tree.nodes.empty() ? gpu::TRACE_NO_ROOT : word(0);
}

} // namespace

TraceMeshBuilder::TraceMeshBuilder(ProbeVolume& volume) : volume_(volume) {
  for (std::size_t i = 0; i < volume.trace_vertices.size(); ++i)
    vertices_[hash_bits(&volume.trace_vertices[i].x, 3)].push_back(std::uint32_t(i));
  for (std::size_t i = 0; i < volume.trace_materials.size(); ++i) {
    const gpu::TraceMaterial& m = volume.trace_materials[i];
    const float values[6] = {m.albedo.x, m.albedo.y, m.albedo.z, m.emission.x, m.emission.y, m.emission.z};
    materials_[hash_bits(values, 6)].push_back(std::uint32_t(i));
  }
}

std::uint32_t TraceMeshBuilder::vertex_in(const glm::vec3& p, VertexMap& vertices) {
  const float xyz[3] = {p.x, p.y, p.z};
  std::vector<std::uint32_t>& same_hash = vertices[hash_bits(xyz, 3)];
  for (std::uint32_t i : same_hash)
    if (same_bits(&volume_.trace_vertices[i].x, xyz, 3)) return i;
  const auto index = std::uint32_t(volume_.trace_vertices.size());
  volume_.trace_vertices.push_back(gpu::TraceVertex{p.x, p.y, p.z});
  same_hash.push_back(index);
  return index;
}

std::uint32_t TraceMeshBuilder::material(const TraceInputTriangle& t) {
  const float values[6] = {t.albedo.x, t.albedo.y, t.albedo.z, t.emission.x, t.emission.y, t.emission.z};
  std::vector<std::uint32_t>& same_hash = materials_[hash_bits(values, 6)];
  for (std::uint32_t i : same_hash) {
    const gpu::TraceMaterial& m = volume_.trace_materials[i];
    const float stored[6] = {m.albedo.x, m.albedo.y, m.albedo.z, m.emission.x, m.emission.y, m.emission.z};
    if (same_bits(stored, values, 6)) return i;
  }
  const auto index = std::uint32_t(volume_.trace_materials.size());
  if (index > gpu::TRACE_MATERIAL_MASK) malformed("more materials than a face's material word holds");
  gpu::TraceMaterial m{};
  m.albedo = t.albedo;
  m.emission = t.emission;
  volume_.trace_materials.push_back(m);
  same_hash.push_back(index);
  return index;
}

gpu::TraceFace TraceMeshBuilder::face(const TraceInputTriangle& t, VertexMap& vertices) {
  gpu::TraceFace face{};
  for (int k = 0; k < 3; ++k) face.vertex[k] = vertex_in(t.corners[k], vertices);
  face.material = material(t) | (t.double_sided ? gpu::TRACE_FACE_DOUBLE_SIDED : 0u);
  return face;
}

void TraceMeshBuilder::check_face_room(std::size_t faces) const {
  if (volume_.trace_faces.size() + faces > std::size_t(gpu::TRACE_LEAF_FIRST_MASK))
    malformed("more faces than a child word holds");
}

int TraceMeshBuilder::add_tree(const TraceTreeInput& tree) {
  check_face_room(tree.triangles.size());
  const std::size_t face_base = volume_.trace_faces.size(), node_base = volume_.trace_nodes.size();
  for (const TraceInputTriangle& t : tree.triangles) volume_.trace_faces.push_back(face(t, vertices_));
  const std::vector<Box> boxes = node_boxes(tree);
  gpu::TraceTree frame = boxes.empty() ? gpu::TraceTree{} : tree_frame(boxes[0]);
  frame.root = append_inner_nodes(volume_.trace_nodes, tree, boxes, frame, face_base);
  frame.node_count = int(volume_.trace_nodes.size() - node_base);
  volume_.trace_trees.push_back(frame);
  return int(volume_.trace_trees.size()) - 1;
}

namespace {

// The top level over cells [first, last): the range halved in the caller's order (Morton: neighbours
// together), so it is ceil(log2(cells)) deep whatever the boxes; nodes in preorder from `next`. (A SAH top
// level over the cell boxes traced about 1 % faster on an H100 at depth 3 and was not kept: docs/results/tracing.md,
// "The static tracing tree by streaming cell (issue #15, first part)".)
// Where the top level splits cells [first, last) of its order (TopLevel::build and cell_top_depths).
std::size_t top_split(std::size_t first, std::size_t last) { return first + (last - first) / 2; }

struct TopLevel {
  const gpu::TraceTree& frame;
  const std::vector<std::uint32_t>& cell_words;
  const std::vector<Box>& cell_boxes;
  std::span<const std::size_t> order; // cell indices
  std::vector<gpu::TraceNode>& nodes; // pre-sized: cells - 1
  std::uint32_t node_base;
  std::uint32_t next = 0;

  std::pair<std::uint32_t, Box> build(std::size_t first, std::size_t last) { // depth ceil(log2(cells))
    if (last - first == 1) return {cell_words[order[first]], cell_boxes[order[first]]};
    const std::uint32_t index = next++;
    const std::size_t middle = top_split(first, last);
    const auto [left_word, left_box] = build(first, middle);
    const auto [right_word, right_box] = build(middle, last);
    gpu::TraceNode& node = nodes[index];
    set_child_box(node, 0, frame, left_box);
    set_child_box(node, 1, frame, right_box);
    node.child[0] = left_word, node.child[1] = right_word;
    Box box = left_box;
    box.grow(right_box);
    return {node_base + index, box};
  }
};

CellRange cell_range(std::size_t first, std::size_t end, std::size_t element_size) {
  CellRange range;
  range.first = std::uint32_t(first);
  range.count = std::uint32_t(end - first);
  range.byte_offset = range.first * element_size;
  range.byte_size = range.count * element_size;
  return range;
}

} // namespace

std::vector<int> cell_top_depths(std::span<const std::size_t> top_order) {
  std::vector<int> depths(top_order.size(), 0);
  const auto descend = [&](const auto& self, std::size_t first, std::size_t last,
                           int depth) -> void { // depth ceil(log2(cells))
    if (last - first == 1) {
      depths.at(top_order[first]) = depth;
      return;
    }
    self(self, first, top_split(first, last), depth + 1);
    self(self, top_split(first, last), last, depth + 1);
  };
  if (!top_order.empty()) descend(descend, 0, top_order.size(), 0);
  return depths;
}

int TraceMeshBuilder::add_cell_tree(std::span<const TraceTreeInput> cells, std::span<const std::size_t> top_order,
                                    std::vector<CellTracing>& ranges) {
  if (top_order.size() != cells.size()) malformed("the top-level order does not list every cell");
  std::size_t total_faces = 0;
  for (const TraceTreeInput& cell : cells) {
    if (cell.nodes.empty()) malformed("a cell without faces");
    total_faces += cell.triangles.size();
  }
  check_face_room(total_faces);
  std::vector<std::vector<Box>> boxes;
  std::vector<Box> cell_boxes;
  Box root;
  for (const TraceTreeInput& cell : cells) {
    boxes.push_back(node_boxes(cell));
    cell_boxes.push_back(boxes.back()[0]);
    root.grow(boxes.back()[0]);
  }
  gpu::TraceTree frame = cells.empty() ? gpu::TraceTree{} : tree_frame(root);
  const std::size_t node_base = volume_.trace_nodes.size();
  const std::size_t top_nodes = cells.empty() ? 0 : cells.size() - 1;
  volume_.trace_nodes.resize(node_base + top_nodes); // the top level, filled once the cells' roots are known
  ranges.assign(cells.size(), CellTracing{});
  std::vector<std::uint32_t> cell_words;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const std::size_t face_base = volume_.trace_faces.size(), vertex_base = volume_.trace_vertices.size(),
                      cell_node_base = volume_.trace_nodes.size();
    VertexMap cell_vertices; // a cell shares no vertex with another
    for (const TraceInputTriangle& t : cells[k].triangles) volume_.trace_faces.push_back(face(t, cell_vertices));
    cell_words.push_back(append_inner_nodes(volume_.trace_nodes, cells[k], boxes[k], frame, face_base));
    ranges[k].trace_nodes = cell_range(cell_node_base, volume_.trace_nodes.size(), sizeof(gpu::TraceNode));
    ranges[k].trace_faces = cell_range(face_base, volume_.trace_faces.size(), sizeof(gpu::TraceFace));
    ranges[k].trace_vertices = cell_range(vertex_base, volume_.trace_vertices.size(), sizeof(gpu::TraceVertex));
  }
  std::vector<gpu::TraceNode> top(top_nodes);
  TopLevel level{frame, cell_words, cell_boxes, top_order, top, std::uint32_t(node_base)};
  frame.root = cells.empty() ? gpu::TRACE_NO_ROOT : level.build(0, cells.size()).first;
  std::copy(top.begin(), top.end(), volume_.trace_nodes.begin() + std::ptrdiff_t(node_base));
  frame.node_count = int(volume_.trace_nodes.size() - node_base);
  volume_.trace_trees.push_back(frame);
  return int(volume_.trace_trees.size()) - 1;
}

namespace {

TraceInputTriangle input_triangle(const gpu::TraceTriangle& t) {
  TraceInputTriangle out;
  out.corners[0] = t.v0;
  out.corners[1] = t.v0 + t.edge1;
  out.corners[2] = t.v0 + t.edge2;
  out.albedo = t.albedo;
  out.emission = t.emission;
  out.double_sided = (t.flags & gpu::TRIANGLE_DOUBLE_SIDED) != 0u;
  return out;
}

// Nodes [first, first + count) and triangles [first_triangle, first_triangle + triangle_count) of a legacy
// tree as a tree-local input.
void add_legacy_tree(const ProbeVolume& v, int first, int count, int first_triangle, int triangle_count,
                     TraceMeshBuilder& builder) {
  if (first < 0 || count < 0 || std::size_t(first) + std::size_t(count) > v.bvh_nodes.size() || first_triangle < 0 ||
      triangle_count < 0 || std::size_t(first_triangle) + std::size_t(triangle_count) > v.trace_triangles.size())
    malformed("a tree's nodes or triangles are out of range");
  std::vector<gpu::BvhNode> nodes(v.bvh_nodes.begin() + first, v.bvh_nodes.begin() + first + count);
  for (gpu::BvhNode& node : nodes) node.first -= node.count == 0 ? first : first_triangle;
  std::vector<TraceInputTriangle> triangles;
  triangles.reserve(std::size_t(triangle_count));
  for (int t = first_triangle; t < first_triangle + triangle_count; ++t)
    triangles.push_back(input_triangle(v.trace_triangles[std::size_t(t)]));
  builder.add_tree(TraceTreeInput{nodes, triangles});
}

} // namespace

void upgrade_tracing(ProbeVolume& volume) {
  if (!has_float_tracing(volume)) return;
  volume.trace_trees.clear(), volume.trace_nodes.clear(), volume.trace_faces.clear();
  volume.trace_vertices.clear(), volume.trace_materials.clear();
  TraceMeshBuilder builder(volume);
  const std::vector<gpu::DynamicObject>& objects = volume.dynamic_objects;
  const int static_nodes = objects.empty() ? int(volume.bvh_nodes.size()) : objects[0].bvh_root;
  const int static_triangles = objects.empty() ? int(volume.trace_triangles.size()) : objects[0].first_triangle;
  add_legacy_tree(volume, 0, static_nodes, 0, static_triangles, builder);
  for (gpu::DynamicObject& object : volume.dynamic_objects) {
    const auto first_face = int(volume.trace_faces.size());
    add_legacy_tree(volume, object.bvh_root, object.bvh_node_count, object.first_triangle, object.triangle_count,
                    builder);
    object.bvh_root = int(volume.trace_trees.size()) - 1;
    object.bvh_node_count = volume.trace_trees.back().node_count;
    object.first_triangle = first_face;
  }
  volume.bvh_nodes.clear();
  volume.trace_triangles.clear();
  sync_info_counts(volume);
}

} // namespace probebake::formats
