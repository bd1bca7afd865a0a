// The runtime lighting sections (stage "gpu_scene", format 1.1; compact tracing 1.4): a test-only
// closest-hit traversal of the baked trace trees (quantised boxes decoded as the shaders do, stack
// traversal, Moller-Trumbore on the shared vertices) finds the same hits as Embree (RayScene::intersect) on
// the Cornell box and the rooms; lights, emitter patches, ray
// directions and LightingInfo are the bake's own values; the bake writes the sections by default.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <span>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/bake/gpu_scene.h"
#include "probebake/common/lattice.h"
#include "probebake/dynamic/animation.h"
#include "probebake/formats/cell_file.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/container.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/trace_mesh.h"
#include "probebake/formats/validate.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

std::string violations(const formats::ValidationReport& r) {
  std::string out;
  for (const auto& v : r.violations) out += formats::format_violation(v) + "\n";
  return out;
}

// An otherwise empty, valid volume with the scene's runtime lighting sections.
formats::ProbeVolume lighting_volume(const scene::Scene& s, const bake::BakeSettings& settings,
                                     bake::RuntimeLightingReport* report = nullptr) {
  gpu::VolumeInfo info{};
  info.root_size = 1.0f;
  info.lattice = int(settings.lattice);
  info.surfels_per_probe = settings.surfels_per_probe;
  formats::ProbeVolume v = formats::make_empty_volume(info);
  const bake::RuntimeLightingReport r = bake::add_runtime_lighting(s, settings, v);
  if (report != nullptr) *report = r;
  return v;
}

// ---- a test-only GPU-style tracer over the baked arrays -------------------------------------------------

struct GpuHit {
  float distance = 0.0f;
  int triangle = -1;      // index into trace_faces
  glm::vec3 normal{0.0f}; // world space (object triangles are stored in their object's frame)
};

// Slab test with the far distance scaled by 1 + 2 gamma(3) (Ize 2013), so that rounding never culls a box
// the ray touches; fmin/fmax ignore the NaN of 0 * inf for a ray inside a slab's plane.
bool hits_box(const formats::TraceBox& box, glm::vec3 origin, glm::vec3 inverse, float t_max) {
  float t_near = 0.0f, t_far = t_max;
  for (int a = 0; a < 3; ++a) {
    const float t0 = (box.lower[a] - origin[a]) * inverse[a], t1 = (box.upper[a] - origin[a]) * inverse[a];
    t_near = std::fmax(t_near, std::fmin(t0, t1));
    t_far = std::fmin(t_far, std::fmax(t0, t1) * 1.0000004f);
  }
  return t_near <= t_far;
}

// Moller-Trumbore, both faces.
std::optional<float> intersect(const formats::TraceFaceGeometry& tri, glm::vec3 origin, glm::vec3 direction) {
  const glm::vec3 p = glm::cross(direction, tri.edge2);
  const float det = glm::dot(tri.edge1, p);
  if (det == 0.0f) return std::nullopt;
  const float inv = 1.0f / det;
  const glm::vec3 s = origin - tri.v0;
  const float u = glm::dot(s, p) * inv;
  if (u < 0.0f || u > 1.0f) return std::nullopt;
  const glm::vec3 q = glm::cross(s, tri.edge1);
  const float v = glm::dot(direction, q) * inv;
  if (v < 0.0f || u + v > 1.0f) return std::nullopt;
  return glm::dot(tri.edge2, q) * inv;
}

// One tree; `best` keeps the nearest hit over the calls (the direction is not normalised in an object's
// frame, so distances are the same in both).
void trace_tree(const formats::ProbeVolume& v, int tree_index, glm::vec3 origin, glm::vec3 direction, GpuHit& best) {
  const gpu::TraceTree& tree = v.trace_trees[std::size_t(tree_index)];
  if (tree.root == gpu::TRACE_NO_ROOT) return;
  const glm::vec3 inverse = 1.0f / direction;
  if (!hits_box(formats::tree_box(tree), origin, inverse, best.distance)) return;
  std::array<std::uint32_t, gpu::BVH_MAX_DEPTH + 1> stack{};
  int size = 0;
  stack[size++] = tree.root;
  while (size > 0) {
    const std::uint32_t word = stack[std::size_t(--size)];
    if (formats::is_leaf_word(word)) {
      for (std::uint32_t f = formats::leaf_first(word); f < formats::leaf_first(word) + formats::leaf_count(word);
           ++f) {
        const formats::TraceFaceGeometry face = formats::face_geometry(v, f);
        const auto d = intersect(face, origin, direction);
        if (d && *d >= 0.0f && *d < best.distance) best = {*d, int(f), face.normal};
      }
      continue;
    }
    const gpu::TraceNode& node = v.trace_nodes[word];
    for (int c = 1; c >= 0; --c)
      if (hits_box(formats::decode_child_box(tree, node, c), origin, inverse, best.distance))
        stack[std::size_t(size++)] = node.child[c];
  }
}

// Two levels, as the runtime traces (bvh_trace.glsl): the static tree, then each dynamic object at rest.
std::optional<GpuHit> trace(const formats::ProbeVolume& v, glm::vec3 origin, glm::vec3 direction) {
  GpuHit best{std::numeric_limits<float>::max(), -1};
  trace_tree(v, 0, origin, direction, best);
  for (std::size_t o = 0; o < v.dynamic_objects.size(); ++o) {
    const glm::mat4 rest = dynamic::rest_pose(v.dynamic_objects[o]), object_from_world = glm::inverse(rest);
    const int before = best.triangle;
    trace_tree(v, int(o) + 1, glm::vec3(object_from_world * glm::vec4(origin, 1.0f)),
               glm::mat3(object_from_world) * direction, best);
    if (best.triangle != before)
      best.normal = glm::normalize(glm::transpose(glm::mat3(object_from_world)) * best.normal);
  }
  if (best.triangle < 0) return std::nullopt;
  return best;
}

// Whether a static face is the scene's triangle `t` (the same corners, bit for bit).
bool is_scene_triangle(const formats::ProbeVolume& v, const scene::Scene& s, std::size_t face, std::uint32_t t) {
  const gpu::TraceFace& f = v.trace_faces[face];
  for (int k = 0; k < 3; ++k) {
    const gpu::TraceVertex& p = v.trace_vertices[f.vertex[k]];
    if (glm::vec3(p.x, p.y, p.z) != s.positions[s.triangles[t][k]]) return false;
  }
  return true;
}

struct Comparison {
  int rays = 0, hits = 0, backfaces = 0, ties = 0, opposite_ties = 0, edge_ties = 0;
  int other_surface = 0; // ties whose surface (albedo, emission or facing) differs from Embree's triangle's
  int only_gpu = 0, only_embree = 0, other_triangle = 0, other_face = 0, far = 0;
  double max_relative = 0.0; // |t_gpu - t_embree| / t over hits farther than 1 % of the scene size
};

// Random origins in the scene bounds (padded 10 %), random directions: rays from inside solids reach back
// faces too. Distances must agree within 1e-5 relative to max(t, scene size): near the origin both
// computations carry the absolute rounding of the coordinates. A different triangle is accepted only as
// a tie (the same distance): on a shared edge, or inside a coplanar overlapping triangle; a tie between
// coincident triangles facing opposite ways (the rooms have some) may also differ in the face.
Comparison compare_with_embree(const scene::Scene& s, const formats::ProbeVolume& v, int rays) {
  const scene::RayScene embree(s);
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> normal;
  const glm::vec3 extent = s.bounds.max - s.bounds.min;
  const double scene_size = std::max({extent.x, extent.y, extent.z});
  const glm::vec3 low = s.bounds.min - 0.1f * extent, size = 1.2f * extent;
  Comparison c;
  for (; c.rays < rays; ++c.rays) {
    const glm::vec3 origin = low + size * glm::vec3(unit(rng), unit(rng), unit(rng));
    const glm::vec3 direction = glm::normalize(glm::vec3(normal(rng), normal(rng), normal(rng)));
    const auto a = embree.intersect(origin, direction);
    const auto b = trace(v, origin, direction);
    if (a.has_value() != b.has_value()) {
      (a ? c.only_embree : c.only_gpu) += 1;
      continue;
    }
    if (!a) continue;
    ++c.hits;
    const double difference = std::abs(double(b->distance) - a->distance);
    c.far += difference > 1e-5 * std::max(double(a->distance), scene_size) ? 1 : 0;
    if (a->distance > 0.01 * scene_size) c.max_relative = std::max(c.max_relative, difference / a->distance);
    const bool backface = glm::dot(b->normal, direction) > 0.0f;
    c.backfaces += backface ? 1 : 0;
    const bool tie = !is_scene_triangle(v, s, std::size_t(b->triangle), a->triangle);
    if (tie && difference > 1e-5 * std::max(double(a->distance), scene_size))
      ++c.other_triangle;
    else if (tie && std::min({a->u, a->v, 1.0f - a->u - a->v}) < 1e-4f)
      ++c.edge_ties;
    else if (tie) {
      (backface == a->backface ? c.ties : c.opposite_ties) += 1;
      const gpu::TraceMaterial& m =
          v.trace_materials[v.trace_faces[std::size_t(b->triangle)].material & gpu::TRACE_MATERIAL_MASK];
      c.other_surface += m.albedo != s.triangle_albedo[a->triangle] || m.emission != s.triangle_emission[a->triangle] ||
                         backface != a->backface;
    } else if (backface != a->backface)
      ++c.other_face;
  }
  return c;
}

void expect_same_hits(const scene::Scene& s, const char* name, float leaf_cost = bake::BakeSettings{}.trace_leaf_cost) {
  bake::BakeSettings settings = test_settings();
  settings.trace_leaf_cost = leaf_cost;
  bake::RuntimeLightingReport report;
  const formats::ProbeVolume volume = lighting_volume(s, settings, &report);
  const formats::ValidationReport validation = formats::validate(volume);
  EXPECT_TRUE(validation.valid()) << violations(validation);
  const Comparison c = compare_with_embree(s, volume, 20000);
  std::printf(
      "[ %s ] %d triangles, %d BVH nodes, depth %d, %.1f ms: %d rays, %d hits (%d back faces), %d ties on a shared "
      "edge, %d inside another triangle (%d between opposite faces, %d with another surface), max relative distance "
      "error %.2g\n",
      name, report.triangles, report.bvh_nodes, report.bvh_depth, 1e3 * report.bvh_seconds, c.rays, c.hits, c.backfaces,
      c.edge_ties, c.ties + c.opposite_ties, c.opposite_ties, c.other_surface, c.max_relative);
  EXPECT_GT(c.hits, c.rays / 4);
  EXPECT_GT(c.backfaces, 0);
  EXPECT_EQ(c.only_gpu, 0);
  EXPECT_EQ(c.only_embree, 0);
  EXPECT_EQ(c.other_triangle, 0);
  EXPECT_EQ(c.other_face, 0);
  EXPECT_EQ(c.far, 0);
  // Rays that end where two coplanar triangles overlap (the rooms have such walls) hit either at the same
  // distance, whichever the traversal meets first: harmless where both have the same surface, so what is
  // bounded is a tie with another surface (coincident triangles facing opposite ways).
  EXPECT_LE(c.other_surface, c.hits / 1000);
  EXPECT_LE(c.ties + c.opposite_ties, c.hits / 100);
  EXPECT_LT(c.max_relative, 1e-5);
}

TEST(GpuScene, TraversalFindsEmbreesHitsInTheCornellBox) {
  const scene::Scene s = load_generated(samples::cornell(), "gpu_cornell");
  expect_same_hits(s, "cornell");
}

TEST(GpuScene, TraversalFindsEmbreesHitsInTheRooms) {
  const scene::Scene s = load_generated(samples::rooms({.count = 4, .detail = 8}), "gpu_rooms");
  ASSERT_GT(s.triangles.size(), 40000u);
  expect_same_hits(s, "rooms");
}

// The leaf cost trades bytes for trace work, never hits: a cost of 1 (Embree's default) gives about twice
// the nodes of the default 0.35 over the same faces, and both trees find Embree's hits.
TEST(GpuScene, LeafCostTradesNodesForLargerLeavesWithTheSameHits) {
  const scene::Scene s = load_generated(samples::rooms({.count = 2, .detail = 4}), "gpu_rooms_cost");
  bake::BakeSettings settings = test_settings();
  bake::RuntimeLightingReport cheap, fast;
  lighting_volume(s, settings, &cheap);
  settings.trace_leaf_cost = 1.0f;
  lighting_volume(s, settings, &fast);
  std::printf("[ leaf cost ] %d faces: cost 0.35 %d nodes, %.1f B per face; cost 1 %d nodes, %.1f B per face\n",
              cheap.triangles, cheap.bvh_nodes, double(cheap.tracing_bytes) / cheap.triangles, fast.bvh_nodes,
              double(fast.tracing_bytes) / fast.triangles);
  EXPECT_EQ(cheap.triangles, fast.triangles);
  EXPECT_GT(fast.bvh_nodes, cheap.bvh_nodes * 3 / 2);
  EXPECT_LT(cheap.tracing_bytes, fast.tracing_bytes);
  expect_same_hits(s, "rooms, leaf cost 1", 1.0f);
  settings.trace_leaf_cost = 0.0f;
  EXPECT_THROW(bake::check_settings(settings), Error);
}

// ---- the static tree split by streaming cell (format 1.5) ----------------------------------------------

// Cell k's part of the static tree as a tree of its own: its nodes, faces and vertices copied out of the
// file's bytes at the cell's byte ranges and renumbered from 0, as a streaming reader would place them.
std::span<const std::uint8_t> section_payload(const formats::ContainerView& view, formats::SectionType type) {
  for (std::size_t i = 0; i < view.sections.size(); ++i)
    if (view.sections[i].type == static_cast<std::uint32_t>(type)) return view.payloads[i];
  return {};
}

formats::ProbeVolume cell_alone(const std::vector<std::uint8_t>& file, const formats::ProbeVolume& v, std::size_t k) {
  const formats::ContainerView view = formats::parse_container(file, "cells");
  const auto payload = [&](formats::SectionType type) { return section_payload(view, type); };
  const formats::CellTracing& ranges = v.cell_tracing[k];
  const auto copy = [&](formats::SectionType type, const formats::CellRange& range, auto& out) {
    const std::span<const std::uint8_t> bytes = payload(type).subspan(range.byte_offset, range.byte_size);
    out.resize(range.count);
    std::memcpy(out.data(), bytes.data(), bytes.size());
  };
  formats::ProbeVolume cell;
  copy(formats::SectionType::trace_nodes, ranges.trace_nodes, cell.trace_nodes);
  copy(formats::SectionType::trace_faces, ranges.trace_faces, cell.trace_faces);
  copy(formats::SectionType::trace_vertices, ranges.trace_vertices, cell.trace_vertices);
  const auto rebase = [&](std::uint32_t word) {
    if (!formats::is_leaf_word(word)) return word - ranges.trace_nodes.first;
    return (word & ~gpu::TRACE_LEAF_FIRST_MASK) | (formats::leaf_first(word) - ranges.trace_faces.first);
  };
  for (gpu::TraceNode& node : cell.trace_nodes)
    for (std::uint32_t& child : node.child) child = rebase(child);
  for (gpu::TraceFace& face : cell.trace_faces)
    for (std::uint32_t& vertex : face.vertex) vertex -= ranges.trace_vertices.first;
  // Its root: its first node, or the top-level leaf word that holds all its faces.
  gpu::TraceTree tree = v.trace_trees[0];
  tree.root = ranges.trace_nodes.count > 0 ? ranges.trace_nodes.first : gpu::TRACE_NO_ROOT;
  for (std::size_t n = 0; tree.root == gpu::TRACE_NO_ROOT && n < v.trace_nodes.size(); ++n)
    for (std::uint32_t child : v.trace_nodes[n].child)
      if (formats::is_leaf_word(child) && formats::leaf_first(child) == ranges.trace_faces.first) tree.root = child;
  tree.root = rebase(tree.root);
  cell.trace_trees.push_back(tree);
  return cell;
}

// The split tree finds Embree's hits like the single one; each cell's part, read alone from the file's
// bytes, is a complete tree over exactly the scene's triangles whose centroid lies in the cell: every ray
// finds what a brute-force test of the cell's faces finds. A tampered cell is refused by validate().
TEST(GpuScene, EachCellsPartOfTheTreeTracesAloneFromItsByteRanges) {
  const scene::Scene s = load_generated(samples::rooms({.count = 4, .detail = 4}), "gpu_rooms_cells");
  bake::BakeSettings settings = test_settings();
  settings.cell_depth = 3;
  gpu::VolumeInfo info = bake::volume_info(s, settings);
  formats::ProbeVolume v = formats::make_empty_volume(info);
  bake::add_runtime_lighting(s, settings, v);
  ASSERT_TRUE(formats::validate(v).valid()) << violations(formats::validate(v));
  ASSERT_EQ(v.cell_tracing.size(), v.cells.size());
  ASSERT_GT(v.cells.size(), 16u);
  const Comparison c = compare_with_embree(s, v, 5000);
  EXPECT_GT(c.hits, c.rays / 4);
  EXPECT_EQ(c.only_gpu + c.only_embree + c.other_triangle + c.other_face + c.far, 0);

  // Each cell's tree starts at the depth the bake planned for it (formats::cell_top_depths), so the whole
  // tree stays under the shaders' stack: the depth of every word of tree 0, from its root.
  std::vector<int> word_depth_of_cell(v.cells.size(), -1);
  std::vector<std::pair<std::uint32_t, int>> stack{{v.trace_trees[0].root, 0}};
  int deepest = 0;
  while (!stack.empty()) {
    const auto [word, word_depth] = stack.back();
    stack.pop_back();
    deepest = std::max(deepest, word_depth);
    for (std::size_t k = 0; k < v.cells.size(); ++k) {
      const formats::CellTracing& r = v.cell_tracing[k];
      const bool cell_root = r.trace_nodes.count > 0
                                 ? word == r.trace_nodes.first
                                 : formats::is_leaf_word(word) && formats::leaf_first(word) == r.trace_faces.first;
      if (cell_root) word_depth_of_cell[k] = word_depth;
    }
    if (!formats::is_leaf_word(word))
      for (std::uint32_t child : v.trace_nodes[word].child) stack.emplace_back(child, word_depth + 1);
  }
  std::vector<std::size_t> order; // the bake's: Morton order of the cells' grid coordinates
  for (std::size_t k = 0; k < v.cells.size(); ++k) order.push_back(k);
  const int n = formats::cells_per_axis(v.cell_depth);
  const auto morton = [&](int cell) {
    std::uint32_t code = 0;
    for (int bit = 0; bit < v.cell_depth; ++bit)
      for (int axis = 0, rest = cell; axis < 3; ++axis, rest /= n)
        code |= std::uint32_t(((rest % n) >> bit) & 1) << (3 * bit + axis);
    return code;
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return morton(v.cells[a].cell_index) < morton(v.cells[b].cell_index);
  });
  EXPECT_EQ(word_depth_of_cell, formats::cell_top_depths(order));
  EXPECT_LT(deepest, gpu::BVH_MAX_DEPTH);

  const std::vector<std::uint8_t> file = formats::write_probes(v);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> normal;
  std::size_t faces = 0, hits = 0;
  for (std::size_t k = 0; k < v.cells.size(); ++k) {
    const formats::ProbeVolume cell = cell_alone(file, v, k);
    faces += cell.trace_faces.size();
    for (std::size_t f = 0; f < cell.trace_faces.size(); ++f) {
      const formats::TraceFaceGeometry g = formats::face_geometry(cell, f);
      const glm::vec3 a = g.v0, b = g.v0 + g.edge1, cc = g.v0 + g.edge2;
      ASSERT_EQ(formats::cell_of_triangle(v.info, v.cell_depth, a, b, cc), v.cells[k].cell_index)
          << "cell " << k << " face " << f;
    }
    if (cell.trace_faces.empty()) continue;
    glm::vec3 lower, upper;
    formats::cell_bounds(v.info, v.cell_depth, v.cells[k].cell_index, lower, upper);
    for (int r = 0; r < 64; ++r) {
      const glm::vec3 origin = lower + (upper - lower) * glm::vec3(unit(rng), unit(rng), unit(rng));
      const glm::vec3 direction = glm::normalize(glm::vec3(normal(rng), normal(rng), normal(rng)));
      GpuHit traced{std::numeric_limits<float>::max(), -1};
      trace_tree(cell, 0, origin, direction, traced);
      float nearest = std::numeric_limits<float>::max();
      for (std::size_t f = 0; f < cell.trace_faces.size(); ++f)
        if (const auto d = intersect(formats::face_geometry(cell, f), origin, direction); d && *d >= 0.0f)
          nearest = std::min(nearest, *d);
      ASSERT_EQ(traced.distance, nearest) << "cell " << k << " ray " << r;
      hits += traced.triangle >= 0 ? 1 : 0;
    }
  }
  std::printf("[ cells ] %zu cells, %zu static faces, %zu of %zu rays from inside cells hit their cell's faces\n",
              v.cells.size(), faces, hits, 64 * v.cells.size());
  ASSERT_FALSE(v.dynamic_objects.empty()); // the rooms' spheres: their faces follow the cells'
  EXPECT_EQ(faces, std::size_t(v.dynamic_objects[0].first_triangle));
  EXPECT_GT(hits, 0u);

  const auto invariants_of = [](const formats::ProbeVolume& tampered) {
    std::set<std::string> ids;
    for (const auto& violation : formats::validate(tampered).violations) ids.insert(violation.invariant);
    return ids;
  };
  formats::ProbeVolume other_vertex = v; // a face that borrows the next cell's vertex
  const std::size_t last = v.cells.size() - 1;
  other_vertex.trace_faces[v.cell_tracing[0].trace_faces.first].vertex[0] = v.cell_tracing[last].trace_vertices.first;
  EXPECT_TRUE(invariants_of(other_vertex).count("cell_tracing"));
  formats::ProbeVolume overlapping = v;
  overlapping.cell_tracing[1].trace_faces.first -= 1,
      overlapping.cell_tracing[1].trace_faces.byte_offset -= sizeof(gpu::TraceFace);
  EXPECT_TRUE(invariants_of(overlapping).count("cell_range"));
}

TEST(GpuScene, EachCellIsCheckedOnItsOwnAgainstItsChecksum) {
  const scene::Scene s = load_generated(samples::rooms({.count = 4, .detail = 4}), "gpu_rooms_cells");
  bake::BakeSettings settings = test_settings();
  settings.cell_depth = 3;
  std::vector<std::uint8_t> file = formats::write_probes(bake::bake(s, settings).volume);
  const formats::ProbeVolume v = formats::read_probes(file, "cells"); // with the checksums the writer stored
  ASSERT_EQ(v.cell_checksums.size(), v.cells.size());
  const formats::ContainerView view = formats::parse_container(file, "cells");
  // What a reader that loads cell k alone reads: its six ranges, straight from the file (file offsets).
  using Section = formats::SectionType;
  const auto file_ranges = [&](std::size_t k) {
    const formats::Cell& c = v.cells[k];
    const formats::CellTracing& t = v.cell_tracing[k];
    const std::pair<Section, const formats::CellRange*> ranges[] = {
        {Section::probes, &c.probes},           {Section::surfel_batches, &c.surfel_batches},
        {Section::svo_leaves, &c.svo_leaves},   {Section::trace_nodes, &t.trace_nodes},
        {Section::trace_faces, &t.trace_faces}, {Section::trace_vertices, &t.trace_vertices}};
    std::vector<std::pair<std::size_t, std::size_t>> out; // offset in the file and bytes of each range, in order
    for (const auto& [section, range] : ranges) {
      const std::span<const std::uint8_t> payload = section_payload(view, section);
      out.emplace_back(range->byte_size == 0 ? 0 : std::size_t(payload.data() - file.data()) + range->byte_offset,
                       range->byte_size);
    }
    return out;
  };
  int cells_with_probes = 0, cells_with_faces = 0;
  for (std::size_t k = 0; k < v.cells.size(); ++k) {
    std::vector<std::uint8_t> bytes;
    for (const auto& [offset, size] : file_ranges(k))
      bytes.insert(bytes.end(), file.begin() + std::ptrdiff_t(offset), file.begin() + std::ptrdiff_t(offset + size));
    EXPECT_EQ(formats::checksum64(bytes), v.cell_checksums[k]) << "cell " << k;
    cells_with_probes += v.cells[k].probes.count > 0 ? 1 : 0;
    cells_with_faces += v.cell_tracing[k].trace_faces.count > 0 ? 1 : 0;
  }
  EXPECT_GT(cells_with_probes, 1);
  EXPECT_GT(cells_with_faces, 1);
  // One damaged byte in a cell's faces, then one in its probes: the validator names that cell and no other
  // (besides the section's own checksum).
  const auto damaged_cells = [&](std::size_t k, std::size_t range) {
    std::vector<std::uint8_t> damaged = file;
    const auto [offset, size] = file_ranges(k).at(range);
    damaged[offset + size / 2] ^= 0x10;
    std::set<long long> named;
    bool section_checksum = false;
    for (const formats::Violation& violation : formats::validate_file(damaged, "damaged", {}).violations) {
      if (violation.invariant == "cell_checksum") named.insert(violation.index);
      section_checksum = section_checksum || violation.invariant == "checksum";
    }
    EXPECT_TRUE(section_checksum);
    return named;
  };
  std::size_t with_faces = 0;
  while (v.cell_tracing[with_faces].trace_faces.count == 0 || v.cells[with_faces].probes.count == 0) ++with_faces;
  EXPECT_EQ(damaged_cells(with_faces, 4), std::set<long long>{static_cast<long long>(with_faces)}) << "a face";
  EXPECT_EQ(damaged_cells(with_faces, 0), std::set<long long>{static_cast<long long>(with_faces)}) << "a probe";
}

// A streaming runtime's reader (formats/cell_file.h): every cell read back from disk equals the cell in the
// volume read whole; a cell whose bytes change on disk after the open, or that the file no longer reaches,
// is refused with its name, and the other cells still read.
TEST(GpuScene, CellFileReadsEachCellFromDiskAndRefusesOneChangedSinceOpen) {
  const scene::Scene s = load_generated(samples::rooms({.count = 4, .detail = 4}), "gpu_rooms_cell_file");
  bake::BakeSettings settings = test_settings();
  settings.cell_depth = 3;
  const std::string path = ::testing::TempDir() + "probebake-cell-file-" + std::to_string(::getpid()) + ".probes";
  formats::write_probes_file(path, bake::bake(s, settings).volume);
  const formats::ProbeVolume v = formats::read_probes_file(path);
  formats::OpenedCellFile opened = formats::CellFile::open(path);
  formats::CellFile& file = opened.file;
  // The load reads none of the cells' tracing (format 1.7): the three sections are the file's outside the
  // cells' ranges and zeros inside them, in zero pages, and the global part is valid without the cells.
  EXPECT_TRUE(opened.cells_unread);
  EXPECT_TRUE(opened.volume.trace_nodes.empty() && opened.volume.trace_faces.empty() &&
              opened.volume.trace_vertices.empty());
  const formats::TracingView in_file = opened.tracing();
  ASSERT_EQ(in_file.faces.size(), v.trace_faces.size());
  std::uint64_t cells_tracing = 0;
  for (std::size_t k = 0; k < v.cells.size(); ++k) {
    const formats::CellTracing& t = v.cell_tracing[k];
    cells_tracing += formats::cell_tracing_bytes(t);
    for (std::uint32_t f = t.trace_faces.first; f < t.trace_faces.first + t.trace_faces.count; ++f)
      ASSERT_EQ(in_file.faces[f].vertex[0] | in_file.faces[f].vertex[1] | in_file.faces[f].material, 0u)
          << "face " << f << " was read";
  }
  const std::uint32_t global_faces = v.cell_tracing.back().trace_faces.first + v.cell_tracing.back().trace_faces.count;
  EXPECT_EQ(std::memcmp(in_file.faces.data() + global_faces, v.trace_faces.data() + global_faces,
                        (v.trace_faces.size() - global_faces) * sizeof(gpu::TraceFace)),
            0);
  EXPECT_EQ(opened.bytes_read, std::filesystem::file_size(path) - cells_tracing);
  std::vector<formats::CellEntry> entries;
  ASSERT_TRUE(formats::validate_without_cells(opened.volume, in_file, entries).valid());
  EXPECT_THROW(file.read_cell_tracing(0), Error) << "before expect_unread()";
  file.expect_unread(opened.volume, entries);
  opened.mapping.reset(); // as Volume::load does once it has uploaded: below, the file changes on disk
  const auto same = [](const formats::CellTracingData& a, const formats::CellTracingData& b) {
    const auto bytes_equal = [](const auto& x, const auto& y) {
      return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
    };
    return bytes_equal(a.nodes, b.nodes) && bytes_equal(a.faces, b.faces) && bytes_equal(a.vertices, b.vertices);
  };
  std::size_t faces = 0;
  for (std::size_t k = 0; k < v.cells.size(); ++k) {
    const formats::CellTracingData read = file.read_cell_tracing(k);
    ASSERT_TRUE(same(read, formats::cell_tracing_data(v, k))) << "cell " << k;
    faces += read.faces.size();
  }
  ASSERT_GT(faces, 0u);
  const formats::ContainerView view = formats::parse_container(formats::read_file_bytes(path), path);
  const auto file_offset = [&](formats::SectionType type, const formats::CellRange& range) {
    for (const formats::SectionEntry& e : view.sections)
      if (e.type == static_cast<std::uint32_t>(type)) return e.offset + range.byte_offset + range.byte_size / 2;
    return std::uint64_t(0);
  };
  const auto flip_byte = [&](std::uint64_t offset) {
    std::fstream out(path, std::ios::in | std::ios::out | std::ios::binary);
    out.seekg(std::streamoff(offset));
    const char byte = char(out.get() ^ 0x10);
    out.seekp(std::streamoff(offset));
    out.put(byte);
  };
  std::size_t damaged = 0;
  while (v.cell_tracing[damaged].trace_faces.count == 0) ++damaged;
  flip_byte(file_offset(formats::SectionType::trace_faces, v.cell_tracing[damaged].trace_faces));
  const auto refusal = [&](std::size_t k) -> std::string {
    try {
      file.read_cell_tracing(k);
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      return e.what();
    }
    return "";
  };
  const std::string changed = refusal(damaged);
  EXPECT_NE(
      changed.find("cells[" + std::to_string(damaged) + "] (cell " + std::to_string(v.cells[damaged].cell_index) + ")"),
      std::string::npos)
      << changed;
  EXPECT_NE(changed.find("differ from their checksum"), std::string::npos) << changed;
  for (std::size_t k = 0; k < v.cells.size(); ++k) {
    if (k == damaged) continue;
    EXPECT_TRUE(same(file.read_cell_tracing(k), formats::cell_tracing_data(v, k))) << "cell " << k;
  }
  // Cut the file in the middle of the last cell's vertices: that cell no longer reads, an earlier one does.
  std::size_t last = v.cells.size() - 1;
  while (v.cell_tracing[last].trace_vertices.count == 0) --last;
  std::filesystem::resize_file(path,
                               file_offset(formats::SectionType::trace_vertices, v.cell_tracing[last].trace_vertices));
  const std::string cut = refusal(last);
  EXPECT_NE(cut.find("cells[" + std::to_string(last) + "]"), std::string::npos) << cut;
  EXPECT_NE(cut.find("bytes early"), std::string::npos) << cut;
  std::size_t first = 0;
  while (first == damaged || v.cell_tracing[first].trace_faces.count == 0) ++first;
  EXPECT_TRUE(same(file.read_cell_tracing(first), formats::cell_tracing_data(v, first)));
  EXPECT_THROW(file.read_volume(), Error) << "the whole file no longer reads";
  std::filesystem::remove(path);
}

TEST(GpuScene, CellSizePicksTheShallowestGridWithCellsThatNarrow) {
  bake::BakeSettings settings;
  settings.cell_depth = 4;
  EXPECT_EQ(bake::cell_depth_for(settings, 10.0f), 4); // no size: the depth as given
  settings.cell_size = 3.0f;
  EXPECT_EQ(bake::cell_depth_for(settings, 10.0f), 2); // 2.5 m cells
  settings.cell_size = 10.0f;
  EXPECT_EQ(bake::cell_depth_for(settings, 10.0f), 0);
  settings.cell_size = 0.3125f;
  EXPECT_EQ(bake::cell_depth_for(settings, 10.0f), 5);
  settings.cell_size = 0.3f; // 32 cells per axis are 0.3125 m wide
  EXPECT_THROW(bake::cell_depth_for(settings, 10.0f), Error);
}

// ---- conversions -------------------------------------------------------------------------------------

samples::SceneBuilder lit_scene() {
  samples::SceneBuilder b = samples::triangle();
  b.add_light_node(
      "spot", b.add_light({"spot", samples::LightType::spot, glm::vec3(1.0f, 0.5f, 0.25f), 50.0f, 4.0f, 0.3f, 0.6f}),
      {0.25f, 2.0f, -0.25f}, glm::normalize(glm::vec3(0.1f, -1.0f, 0.2f)));
  b.add_light_node("sun", b.add_light({"sun", samples::LightType::directional, glm::vec3(0.5f), 3.0f}), {5, 5, 5},
                   glm::normalize(glm::vec3(1.0f, -2.0f, 0.5f)));
  return b;
}

TEST(GpuScene, PunctualLightsAreTheBakesFormulas) {
  const scene::Scene s = load_generated(lit_scene(), "gpu_lights");
  bake::BakeSettings settings = test_settings();
  formats::ProbeVolume v = lighting_volume(s, settings);
  ASSERT_EQ(s.lights.size(), 3u);
  ASSERT_EQ(v.punctual_lights.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const scene::Light& in = s.lights[i];
    const gpu::PunctualLight& out = v.punctual_lights[i];
    SCOPED_TRACE(in.name);
    EXPECT_EQ(out.intensity, in.color * in.intensity);
    EXPECT_EQ(out.pad0, 0.0f);
    if (in.type == scene::LightType::point) {
      EXPECT_EQ(out.type, gpu::LIGHT_POINT);
      EXPECT_EQ(out.position, in.position);
      EXPECT_EQ(out.direction, glm::vec3(0.0f));
      EXPECT_EQ(out.intensity, glm::vec3(10.0f)); // the triangle scene's 10 cd light
    } else if (in.type == scene::LightType::spot) {
      EXPECT_EQ(out.type, gpu::LIGHT_SPOT);
      EXPECT_EQ(out.position, in.position);
      EXPECT_EQ(out.direction, in.direction);
      EXPECT_EQ(out.range, 4.0f);
      EXPECT_EQ(out.intensity, glm::vec3(50.0f, 25.0f, 12.5f));
      const float cos_outer = std::cos(in.outer_cone_angle);
      EXPECT_EQ(out.cos_outer, cos_outer);
      EXPECT_EQ(out.spot_scale, 1.0f / std::max(0.001f, std::cos(in.inner_cone_angle) - cos_outer));
      EXPECT_NEAR(out.cos_outer, std::cos(0.6), 1e-6);
      EXPECT_NEAR(out.spot_scale, 1.0 / (std::cos(0.3) - std::cos(0.6)), 1e-3);
    } else {
      EXPECT_EQ(out.type, gpu::LIGHT_DIRECTIONAL);
      EXPECT_EQ(out.direction, in.direction);
      EXPECT_NEAR(glm::dot(out.direction, glm::normalize(glm::vec3(1.0f, -2.0f, 0.5f))), 1.0f, 1e-6f);
      EXPECT_EQ(out.position, glm::vec3(0.0f));
      EXPECT_EQ(out.range, 0.0f);
      EXPECT_EQ(out.intensity, glm::vec3(1.5f));
    }
  }
  EXPECT_TRUE(v.emitter_patches.empty()); // no emissive triangle
  EXPECT_TRUE(formats::validate(v).valid()) << violations(formats::validate(v));
}

// docs/LIGHTING.md: the Cornell light is 2 triangles x 25 patches; each patch keeps its triangle's normal
// and radiance and the patches tile the triangles (their areas add up).
TEST(GpuScene, EmitterPatchesTileTheCornellLight) {
  const scene::Scene s = load_generated(samples::cornell(), "gpu_patches");
  bake::BakeSettings settings = test_settings();
  formats::ProbeVolume v = lighting_volume(s, settings);
  ASSERT_EQ(v.emitter_patches.size(), 50u);
  double emitter_area = 0.0, patch_area = 0.0;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    if (s.triangle_emission[t].x > 0.0f) emitter_area += scene::triangle_area(s, t);
  }
  const glm::vec3 radiance(samples::cornell_light_radiance[0], samples::cornell_light_radiance[1],
                           samples::cornell_light_radiance[2]);
  for (const gpu::EmitterPatch& p : v.emitter_patches) {
    patch_area += 0.5 * glm::length(glm::cross(p.b - p.a, p.c - p.a));
    EXPECT_EQ(p.radiance, radiance);
    EXPECT_NEAR(p.normal.y, -1.0f, 1e-6f);                                 // facing down from the ceiling
    EXPECT_GT(glm::dot(glm::cross(p.b - p.a, p.c - p.a), p.normal), 0.0f); // counter-clockwise from the front
  }
  EXPECT_NEAR(patch_area, emitter_area, 1e-6 * emitter_area);
  EXPECT_EQ(v.lighting->emissive_as_lights, 1);

  settings.lighting.emissive_as_lights = false; // emitters then reach the runtime through the probes
  bake::add_runtime_lighting(s, settings, v);
  EXPECT_TRUE(v.emitter_patches.empty());
  EXPECT_EQ(v.lighting->emissive_as_lights, 0);
  EXPECT_EQ(v.lighting->emitter_patches, 0);
}

// glTF doubleSided (#19): each trace triangle's flag is its material's, each patch its emitter's; the file
// becomes 1.2 and stays valid. A floor (single-sided), a double-sided wall, a single-sided emitter and a
// double-sided one.
samples::SceneBuilder mixed_sides_scene() {
  samples::SceneBuilder b("mixed_sides");
  const samples::MaterialId floor = b.add_material({"floor", glm::vec3(0.5f), {}});
  const samples::MaterialId wall = b.add_material({"wall", glm::vec3(0.7f), {}, true});
  const samples::MaterialId one_side = b.add_material({"lamp_one_side", glm::vec3(0.5f), glm::vec3(3.0f)});
  const samples::MaterialId two_sides = b.add_material({"lamp_two_sides", glm::vec3(0.5f), glm::vec3(5.0f), true});
  b.add_mesh_node("floor", b.add_mesh("floor", samples::quad({-1, 0, 1}, {2, 0, 0}, {0, 0, -2}), floor));
  b.add_mesh_node("wall", b.add_mesh("wall", samples::quad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}, 2), wall));
  b.add_mesh_node("lamp1",
                  b.add_mesh("lamp1", samples::quad({-0.5f, 1.5f, 0.5f}, {0, 0, -0.3f}, {0.3f, 0, 0}), one_side));
  b.add_mesh_node("lamp2",
                  b.add_mesh("lamp2", samples::quad({0.2f, 1.5f, 0.5f}, {0.3f, 0, 0}, {0, 0, -0.3f}), two_sides));
  return b;
}

TEST(GpuScene, DoubleSidedFlagsAreTheMaterials) {
  const scene::Scene s = load_generated(mixed_sides_scene(), "gpu_sides");
  bake::BakeSettings settings = test_settings();
  const formats::ProbeVolume v = lighting_volume(s, settings);
  ASSERT_EQ(v.trace_faces.size(), 2u + 8u + 2u + 2u);
  int flagged = 0;
  for (std::size_t f = 0; f < v.trace_faces.size(); ++f) {
    std::uint32_t source = 0;
    while (source < s.triangles.size() && !is_scene_triangle(v, s, f, source)) ++source;
    ASSERT_LT(source, s.triangles.size()) << f;
    const bool flag = (v.trace_faces[f].material & gpu::TRACE_FACE_DOUBLE_SIDED) != 0u;
    EXPECT_EQ(flag, scene::is_double_sided(s, source)) << source;
    flagged += flag ? 1 : 0;
  }
  EXPECT_EQ(flagged, 8 + 2); // the wall and the two-sided lamp
  int one_side = 0, two_sides = 0;
  const std::uint32_t first_lamp = v.emitter_patches.at(0).emitter;
  for (const gpu::EmitterPatch& p : v.emitter_patches) {
    // The lamps differ in radiance: 3 (single-sided, faces down) and 5 (double-sided, faces up).
    const bool double_sided = p.radiance.x > 4.0f;
    EXPECT_EQ(p.flags, double_sided ? gpu::EMITTER_DOUBLE_SIDED : 0u);
    // Their two materials are two emitters (format 1.10).
    EXPECT_EQ(p.emitter == first_lamp, double_sided == (v.emitter_patches[0].radiance.x > 4.0f));
    EXPECT_NEAR(p.normal.y, double_sided ? 1.0f : -1.0f, 1e-6f);
    (double_sided ? two_sides : one_side) += 1;
  }
  EXPECT_GT(one_side, 0);
  EXPECT_GT(two_sides, 0);
  EXPECT_EQ(std::size_t(one_side + two_sides), v.emitter_patches.size());
  const formats::ValidationReport validation = formats::validate(v);
  EXPECT_TRUE(validation.valid()) << violations(validation);
  EXPECT_EQ(formats::parse_container(formats::write_probes(v), "sides").header.version_minor,
            formats::kEmitterGroupsMinor);
}

TEST(GpuScene, LightingInfoAndRayDirectionsAreTheBakes) {
  scene::Scene s = load_generated(samples::cornell(), "gpu_info");
  scene::set_sky(s, sky::constant_sky(glm::vec3(0.5f, 0.25f, 2.0f)));
  bake::BakeSettings settings = test_settings();
  settings.lighting.rays = 100;
  settings.lattice = Lattice::equal_area;
  settings.surfels_per_probe = 40;
  const formats::ProbeVolume v = lighting_volume(s, settings);
  ASSERT_TRUE(v.lighting.has_value());
  const gpu::LightingInfo& info = *v.lighting;
  const glm::vec3 extent = s.bounds.max - s.bounds.min;
  EXPECT_EQ(info.shadow_offset, 1e-4f * std::max({extent.x, extent.y, extent.z}));
  EXPECT_NEAR(info.shadow_offset, 1e-4f * 0.5592f, 1e-7f); // the box is 0.5592 m deep
  EXPECT_EQ(info.rays, 100);
  EXPECT_EQ(info.placement_rays, 40);
  EXPECT_EQ(info.sky_radiance, glm::vec3(0.5f, 0.25f, 2.0f));
  EXPECT_TRUE(v.sky.empty()); // a constant sky needs no map
  EXPECT_EQ(info.triangles, 32);
  EXPECT_EQ(info.bvh_nodes, int(v.trace_nodes.size()));
  ASSERT_EQ(v.ray_directions.size(), 140u);
  const auto lighting = lattice_directions(Lattice::fibonacci, 100);
  const auto placement = lattice_directions(Lattice::equal_area, 40);
  for (std::size_t i = 0; i < 100; ++i) EXPECT_EQ(v.ray_directions[i], glm::vec4(lighting[i], 0.0f)) << i;
  for (std::size_t i = 0; i < 40; ++i) EXPECT_EQ(v.ray_directions[100 + i], glm::vec4(placement[i], 0.0f)) << i;
  EXPECT_TRUE(formats::validate(v).valid()) << violations(formats::validate(v));
}

// Zero-area triangles are never hit: left out. No triangles at all: an empty BVH, still valid.
TEST(GpuScene, ZeroAreaTrianglesAreLeftOutAndAnEmptySceneHasNoNodes) {
  scene::Scene s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, -1}, {2, 0, 0}};
  s.triangles = {{0, 1, 2}, {0, 1, 3}, {1, 1, 2}};
  s.triangle_albedo.assign(3, glm::vec3(0.5f));
  s.triangle_emission.assign(3, glm::vec3(0.0f));
  s.materials.resize(1); // the Scene contract: at least one material, one per triangle
  s.triangle_material.assign(3, 0);
  for (const glm::vec3& p : s.positions) s.bounds.extend(p);
  bake::BakeSettings settings = test_settings();
  bake::RuntimeLightingReport report;
  formats::ProbeVolume v = lighting_volume(s, settings, &report);
  EXPECT_EQ(report.left_out_triangles, 2);
  ASSERT_EQ(v.trace_faces.size(), 1u);
  EXPECT_TRUE(is_scene_triangle(v, s, 0, 0));
  EXPECT_EQ(formats::face_geometry(v, 0).normal, glm::vec3(0, 1, 0));
  EXPECT_EQ(v.trace_vertices.size(), 3u);
  ASSERT_EQ(v.trace_trees.size(), 1u);
  EXPECT_TRUE(v.trace_nodes.empty()); // the root is the leaf
  EXPECT_EQ(v.trace_trees[0].root, gpu::TRACE_CHILD_LEAF | 0u);
  EXPECT_EQ(v.trace_trees[0].lower, glm::vec3(0, 0, -1));
  const formats::TraceBox box = formats::tree_box(v.trace_trees[0]);
  EXPECT_EQ(box.upper.y, 0.0f); // flat: scale 0
  EXPECT_GE(box.upper.x, 1.0f);
  EXPECT_LE(box.upper.x, 1.0f + 1e-6f);
  EXPECT_TRUE(formats::validate(v).valid()) << violations(formats::validate(v));

  const scene::Scene empty;
  bake::add_runtime_lighting(empty, settings, v);
  EXPECT_TRUE(v.trace_nodes.empty() && v.trace_faces.empty() && v.trace_vertices.empty());
  ASSERT_EQ(v.trace_trees.size(), 1u);
  EXPECT_EQ(v.trace_trees[0].root, gpu::TRACE_NO_ROOT);
  EXPECT_EQ(v.lighting->shadow_offset, 1e-4f);
  EXPECT_TRUE(formats::validate(v).valid()) << violations(formats::validate(v));
}

// ---- in the bake ----------------------------------------------------------------------------------------

std::vector<std::uint32_t> section_types(const std::vector<std::uint8_t>& bytes) {
  std::vector<std::uint32_t> types;
  for (const formats::SectionEntry& e : formats::parse_container(bytes, "bake").sections) types.push_back(e.type);
  return types;
}

bool has_section(const std::vector<std::uint32_t>& types, formats::SectionType type) {
  return std::find(types.begin(), types.end(), static_cast<std::uint32_t>(type)) != types.end();
}

TEST(GpuScene, BakeWritesTheSectionsUnlessTurnedOff) {
  const scene::Scene s = load_generated(lit_scene(), "gpu_bake");
  bake::BakeSettings settings = test_settings();
  settings.lighting.enabled = false;          // the runtime can light from zero
  settings.placement = bake::Placement::grid; // the octree places no probe around a lone triangle
  settings.grid_resolution = 2;
  const bake::BakeResult with = bake::bake(s, settings);
  EXPECT_TRUE(formats::validate(with.volume).valid()) << violations(formats::validate(with.volume));
  EXPECT_TRUE(with.report.runtime_lighting.written);
  EXPECT_EQ(with.report.runtime_lighting.triangles, 1);
  EXPECT_EQ(with.report.runtime_lighting.lights, 3);
  const auto stage = std::find_if(with.report.stages.begin(), with.report.stages.end(),
                                  [](const auto& t) { return t.stage == "gpu_scene"; });
  EXPECT_NE(stage, with.report.stages.end());
  const std::vector<std::uint8_t> bytes = formats::write_probes(with.volume);
  EXPECT_EQ(formats::parse_container(bytes, "bake").header.version_minor, formats::kCellGlobalChecksumsMinor);
  const auto types = section_types(bytes);
  for (auto type :
       {formats::SectionType::lighting_info, formats::SectionType::ray_directions, formats::SectionType::trace_trees,
        formats::SectionType::trace_faces, formats::SectionType::trace_vertices, formats::SectionType::trace_materials,
        formats::SectionType::punctual_lights}) {
    EXPECT_TRUE(has_section(types, type)) << formats::section_name(static_cast<std::uint32_t>(type));
  }
  EXPECT_FALSE(has_section(types, formats::SectionType::emitter_patches)); // no emitters
  EXPECT_FALSE(has_section(types, formats::SectionType::trace_nodes));     // one triangle: the root is a leaf
  EXPECT_FALSE(has_section(types, formats::SectionType::bvh_nodes) ||
               has_section(types, formats::SectionType::trace_triangles));

  settings.runtime_lighting = false;
  const bake::BakeResult without = bake::bake(s, settings);
  EXPECT_FALSE(without.volume.lighting.has_value());
  EXPECT_FALSE(without.report.runtime_lighting.written);
  const std::vector<std::uint8_t> plain = formats::write_probes(without.volume);
  EXPECT_EQ(formats::parse_container(plain, "bake").header.version_minor, 0);
  for (std::uint32_t type : section_types(plain)) EXPECT_LE(type, 10u);
  EXPECT_NE(bake::bake_input_hash(s, settings), with.volume.input_hash); // the setting is an input
}

} // namespace
} // namespace probebake::test
