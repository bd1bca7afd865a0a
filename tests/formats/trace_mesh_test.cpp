// Compact tracing (format 1.4, trace_mesh.h): the quantised boxes hold their faces under both roundings of
// the decoding on random, extreme and flat trees; 1.1-1.3 volumes upgrade to the same triangles in the same
// order; vertices and materials are shared.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "probebake/formats/trace_mesh.h"
#include "probebake/formats/validate.h"
#include "sample_volumes.h"

namespace probebake::formats {
namespace {

std::string first_violation(const ProbeVolume& v) {
  const ValidationReport report = validate(v);
  return report.violations.empty() ? "" : format_violation(report.violations.front());
}

// A volume with lighting and nothing traced yet, so that trees can be added and validated.
ProbeVolume empty_lit_volume() {
  ProbeVolume v = testing::make_sample(testing::Sample::lighting);
  v.bvh_nodes.clear(), v.trace_triangles.clear();
  return v;
}

// A median-split tree over `triangles` (reordered into leaf order), leaves of up to `leaf` triangles.
std::vector<gpu::BvhNode> median_tree(std::vector<TraceInputTriangle>& triangles, int leaf) {
  std::vector<gpu::BvhNode> nodes(1);
  struct Range {
    int node, first, count;
  };
  std::vector<Range> stack{{0, 0, int(triangles.size())}};
  while (!stack.empty()) {
    const Range r = stack.back();
    stack.pop_back();
    if (r.count <= leaf) {
      nodes[std::size_t(r.node)] = gpu::BvhNode{{}, r.first, {}, r.count};
      continue;
    }
    const int axis = int(nodes.size() % 3);
    std::sort(triangles.begin() + r.first, triangles.begin() + r.first + r.count,
              [&](const TraceInputTriangle& a, const TraceInputTriangle& b) {
                return a.corners[0][axis] < b.corners[0][axis];
              });
    const int child = int(nodes.size());
    nodes.resize(nodes.size() + 2);
    nodes[std::size_t(r.node)] = gpu::BvhNode{{}, child, {}, 0};
    stack.push_back({child + 1, r.first + r.count / 2, r.count - r.count / 2});
    stack.push_back({child, r.first, r.count / 2});
  }
  return nodes;
}

// Every face inside every box above it, decoded with a separate multiply and add and with one fma.
void expect_boxes_hold_faces(const ProbeVolume& v, std::size_t tree_index) {
  const gpu::TraceTree& tree = v.trace_trees[tree_index];
  struct Pending {
    std::uint32_t word;
    TraceBox box;
  };
  std::vector<Pending> stack{{tree.root, tree_box(tree)}};
  const auto fused_box = [&](const gpu::TraceNode& node, int c) {
    TraceBox b;
    const int shift = c == 0 ? 0 : 16;
    for (int a = 0; a < 3; ++a) {
      b.lower[a] = std::fma(float((node.lower[a] >> shift) & 0xFFFFu), tree.scale[a], tree.lower[a]);
      b.upper[a] = std::fma(float((node.upper[a] >> shift) & 0xFFFFu), tree.scale[a], tree.lower[a]);
    }
    return b;
  };
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    if (!is_leaf_word(p.word)) {
      const gpu::TraceNode& node = v.trace_nodes[p.word];
      for (int c = 0; c < 2; ++c) {
        const TraceBox plain = decode_child_box(tree, node, c), fused = fused_box(node, c);
        stack.push_back({node.child[c],
                         {glm::max(p.box.lower, glm::max(plain.lower, fused.lower)),
                          glm::min(p.box.upper, glm::min(plain.upper, fused.upper))}});
      }
      continue;
    }
    for (std::uint32_t f = leaf_first(p.word); f < leaf_first(p.word) + leaf_count(p.word); ++f)
      for (std::uint32_t k : v.trace_faces[f].vertex) {
        const gpu::TraceVertex& q = v.trace_vertices[k];
        const glm::vec3 point(q.x, q.y, q.z);
        ASSERT_TRUE(glm::all(glm::greaterThanEqual(point, p.box.lower)) &&
                    glm::all(glm::lessThanEqual(point, p.box.upper)))
            << "tree " << tree_index << " face " << f;
      }
  }
}

TEST(TraceMesh, QuantisedBoxesHoldTheirFacesOnRandomAndExtremeScenes) {
  std::mt19937 rng(7);
  struct Case {
    float offset, extent, size;
  };
  // Offsets far from the origin (coarse floats), tiny and huge extents, slivers much smaller than a step.
  const Case cases[] = {{0, 10, 0.5f},    {1e4f, 100, 1},    {-3e5f, 1, 1e-3f},
                        {1e6f, 1e5f, 10}, {5, 1e-3f, 1e-4f}, {0, 1e-30f, 1e-31f}};
  for (const Case& c : cases) {
    ProbeVolume v = empty_lit_volume();
    std::uniform_real_distribution<float> at(c.offset, c.offset + c.extent), edge(-c.size, c.size);
    std::vector<TraceInputTriangle> triangles(600);
    for (TraceInputTriangle& t : triangles) {
      t.corners[0] = glm::vec3(at(rng), at(rng), at(rng));
      t.corners[1] = t.corners[0] + glm::vec3(edge(rng), edge(rng), edge(rng));
      t.corners[2] = t.corners[0] + glm::vec3(edge(rng), edge(rng), edge(rng));
      t.albedo = glm::vec3(0.5f);
    }
    const std::vector<gpu::BvhNode> nodes = median_tree(triangles, gpu::TRACE_MAX_LEAF_FACES);
    TraceMeshBuilder builder(v);
    ASSERT_EQ(builder.add_tree(TraceTreeInput{nodes, triangles}), 0);
    expect_boxes_hold_faces(v, 0);
    for (const gpu::TraceTree& tree : v.trace_trees) EXPECT_TRUE(std::isfinite(tree_box(tree).upper.x)) << c.offset;
  }
}

// Every triangle of a flat floor lies in a plane: the frame's y step is 0 and boxes stay exact there.
TEST(TraceMesh, FlatTreesKeepAZeroStep) {
  ProbeVolume v = empty_lit_volume();
  std::vector<TraceInputTriangle> triangles;
  for (int i = 0; i < 20; ++i) {
    TraceInputTriangle t;
    t.corners[0] = glm::vec3(float(i), 2.5f, 0.0f), t.corners[1] = glm::vec3(float(i) + 1, 2.5f, 0.0f),
    t.corners[2] = glm::vec3(float(i), 2.5f, 1.0f);
    triangles.push_back(t);
  }
  const std::vector<gpu::BvhNode> nodes = median_tree(triangles, 2);
  TraceMeshBuilder(v).add_tree(TraceTreeInput{nodes, triangles});
  EXPECT_EQ(v.trace_trees[0].scale.y, 0.0f);
  EXPECT_EQ(tree_box(v.trace_trees[0]).upper.y, 2.5f);
  expect_boxes_hold_faces(v, 0);
  EXPECT_EQ(v.trace_vertices.size(), 21u + 20u); // (i, 0) for i in 0..20 and (i, 1) for i in 0..19: neighbours share
  EXPECT_EQ(v.trace_materials.size(), 1u);
}

// A 1.3 volume upgrades to faces whose corners are the float triangles' v0, v0 + edge1, v0 + edge2, in the
// same order, with the same surfaces, trees and object ranges; the result validates.
TEST(TraceMesh, UpgradeKeepsEveryTriangleInOrder) {
  for (const testing::Sample sample :
       {testing::Sample::lighting, testing::Sample::double_sided, testing::Sample::dynamic}) {
    const ProbeVolume before = testing::make_sample(sample);
    ProbeVolume after = before;
    upgrade_tracing(after);
    EXPECT_EQ(first_violation(after), "") << testing::sample_name(sample);
    EXPECT_TRUE(after.bvh_nodes.empty() && after.trace_triangles.empty());
    ASSERT_EQ(after.trace_faces.size(), before.trace_triangles.size());
    ASSERT_EQ(after.trace_trees.size(), 1 + before.dynamic_objects.size());
    EXPECT_EQ(after.lighting->triangles, int(after.trace_faces.size()));
    for (std::size_t f = 0; f < after.trace_faces.size(); ++f) {
      const gpu::TraceTriangle& t = before.trace_triangles[f];
      const glm::vec3 expected[3] = {t.v0, t.v0 + t.edge1, t.v0 + t.edge2};
      for (int k = 0; k < 3; ++k) {
        const gpu::TraceVertex& p = after.trace_vertices[after.trace_faces[f].vertex[k]];
        EXPECT_EQ(glm::vec3(p.x, p.y, p.z), expected[k]) << f;
      }
      const gpu::TraceMaterial& m = after.trace_materials[after.trace_faces[f].material & gpu::TRACE_MATERIAL_MASK];
      EXPECT_EQ(m.albedo, t.albedo);
      EXPECT_EQ(m.emission, t.emission);
      EXPECT_EQ((after.trace_faces[f].material & gpu::TRACE_FACE_DOUBLE_SIDED) != 0u,
                (t.flags & gpu::TRIANGLE_DOUBLE_SIDED) != 0u);
      EXPECT_LT(glm::length(face_geometry(after, f).normal - t.normal), 1e-6f) << f;
    }
    for (std::size_t o = 0; o < after.dynamic_objects.size(); ++o) {
      EXPECT_EQ(after.dynamic_objects[o].bvh_root, int(o) + 1);
      EXPECT_EQ(after.dynamic_objects[o].first_triangle, before.dynamic_objects[o].first_triangle);
    }
    for (std::size_t t = 0; t < after.trace_trees.size(); ++t) expect_boxes_hold_faces(after, t);
  }
}

// A closed cube: 12 faces over 8 shared vertices; two materials; the bytes are what the sections hold.
TEST(TraceMesh, CubeSharesItsEightCorners) {
  ProbeVolume v = empty_lit_volume();
  std::vector<TraceInputTriangle> triangles;
  for (int axis = 0; axis < 3; ++axis)
    for (const float side : {0.0f, 1.0f}) {
      glm::vec3 q[4];
      for (int i = 0; i < 4; ++i) {
        q[i][axis] = side;
        q[i][(axis + 1) % 3] = float(i == 1 || i == 2);
        q[i][(axis + 2) % 3] = float(i >= 2);
      }
      for (const auto& [a, b] : {std::pair{1, 2}, std::pair{2, 3}}) {
        TraceInputTriangle t;
        t.corners[0] = q[0], t.corners[1] = q[a], t.corners[2] = q[b];
        t.albedo = glm::vec3(axis == 1 ? 0.8f : 0.4f);
        triangles.push_back(t);
      }
    }
  const std::vector<gpu::BvhNode> nodes = median_tree(triangles, 4);
  TraceMeshBuilder(v).add_tree(TraceTreeInput{nodes, triangles});
  EXPECT_EQ(v.trace_vertices.size(), 8u);
  EXPECT_EQ(v.trace_materials.size(), 2u);
  EXPECT_EQ(v.trace_nodes.size(), 3u); // 12 -> 6 + 6 -> four leaves of 3
  EXPECT_EQ(tracing_bytes(v), 32u + 3u * 32u + 12u * 16u + 8u * 12u + 2u * 32u);
}

} // namespace
} // namespace probebake::formats
