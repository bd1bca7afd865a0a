// The validator: the samples are valid, and one hand-made corruption per invariant is reported with
// exactly that invariant as the first violation. Sample layout (see sample_volumes.cpp): root cluster 1
// (nodes 2..9); node 2 -> cluster 10 (11..18), node 9 -> cluster 19 (20..27), node 7 -> cluster 37
// (38..45); cluster 28 is free; leaves 3, 12, 25, 43 hold no probe; SVO node 1+7 = 8 has children 17..24.
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "probebake/formats/cell_file.h"
#include "probebake/formats/container.h"
#include "probebake/formats/grid_lattice.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "sample_volumes.h"

namespace probebake::formats {
namespace {

using testing::Sample;

std::string violations_text(const ValidationReport& report) {
  std::string text;
  for (const Violation& v : report.violations) text += "  " + format_violation(v) + "\n";
  return text;
}

std::vector<int> chain_of(const ProbeVolume& v, int probe) {
  std::vector<int> chain;
  for (int link = v.probes[probe].link; link < 0 && ~link != gpu::PROBE_NO_SURFELS;
       link = v.surfel_batches[chain.back()].link) {
    chain.push_back(~link);
  }
  return chain;
}

// First allocated probe whose chain has at least `batches` batches, searching from the end when asked.
int probe_with_chain(const ProbeVolume& v, std::size_t batches, bool from_end = false) {
  for (std::size_t i = 0; i < v.probes.size(); ++i) {
    const std::size_t p = from_end ? v.probes.size() - 1 - i : i;
    if (v.probes[p].link != 0 && chain_of(v, static_cast<int>(p)).size() >= batches) return static_cast<int>(p);
  }
  return -1;
}

int first_free_probe(const ProbeVolume& v) {
  for (std::size_t p = 0; p < v.probes.size(); ++p) {
    if (v.probes[p].link == 0) return static_cast<int>(p);
  }
  return -1;
}

int first_free_batch(const ProbeVolume& v) {
  for (std::size_t b = 0; b < v.surfel_batches.size(); ++b) {
    if (v.surfel_batches[b].link == 0) return static_cast<int>(b);
  }
  return -1;
}

// The first batch of the first probe that has surfels (a full batch of 16 in the samples).
gpu::SurfelBatch& first_batch(ProbeVolume& v) { return v.surfel_batches[chain_of(v, probe_with_chain(v, 1)).front()]; }

std::vector<int> svo_leaf_nodes(const ProbeVolume& v) {
  std::vector<int> nodes;
  for (std::size_t n = 0; n < v.svo_nodes.size(); ++n) {
    if (v.svo_nodes[n] < 0) nodes.push_back(static_cast<int>(n));
  }
  return nodes;
}

// Replaces the sample's BVH by a chain whose deepest leaf is at `depth`: inner node 2k has the leaf 2k + 1
// (triangle k) and the next inner node 2k + 2; node 2 * depth is the last leaf. All boxes are one box.
void make_bvh_chain(ProbeVolume& v, int depth) {
  const gpu::TraceTriangle triangle = v.trace_triangles[5];
  const gpu::BvhNode box = v.bvh_nodes[4];
  v.trace_triangles.assign(static_cast<std::size_t>(depth) + 1, triangle);
  v.bvh_nodes.clear();
  for (int k = 0; k < depth; ++k) {
    v.bvh_nodes.push_back(gpu::BvhNode{box.lower, 2 * k + 1, box.upper, 0});
    v.bvh_nodes.push_back(gpu::BvhNode{box.lower, k, box.upper, 1});
  }
  v.bvh_nodes.push_back(gpu::BvhNode{box.lower, depth, box.upper, 1});
  sync_info_counts(v);
}

struct Corruption {
  const char* invariant;
  Sample sample;
  std::function<void(ProbeVolume&)> corrupt;
};

const std::vector<Corruption>& corruptions() {
  static const std::vector<Corruption> list = {
      {"volume_info", Sample::small, [](ProbeVolume& v) { v.info.lattice = 7; }},
      {"volume_info", Sample::small, [](ProbeVolume& v) { v.info.split_low = -0.125f; }},
      {"volume_info", Sample::small, [](ProbeVolume& v) { v.info.split_high = 1.5f; }},
      {"volume_info", Sample::small, [](ProbeVolume& v) { v.info.surfels_per_probe = 0; }},
      {"volume_info", Sample::small, [](ProbeVolume& v) { v.info.surfels_per_probe = kMaxSurfelsPerProbe + 1; }},
      {"grid_resolution", Sample::grid, [](ProbeVolume& v) { v.info.grid_resolution = 1 << 20; }},
      {"grid_resolution", Sample::grid, [](ProbeVolume& v) { v.info.grid_resolution = 0; }},
      {"grid_resolution", Sample::grid, [](ProbeVolume& v) { v.info.grid_resolution = 1; }},  // 8 probes > 1^3
      {"grid_resolution", Sample::small, [](ProbeVolume& v) { v.info.grid_resolution = 4; }}, // octree placement
      {"cell_depth", Sample::small, [](ProbeVolume& v) { v.cell_depth = 9; }},
      {"cell_depth", Sample::small, [](ProbeVolume& v) { v.cells.clear(); }}, // depth 1 without cells
      {"section_dependency", Sample::small,
       [](ProbeVolume& v) {
         v.probes.clear(), v.probe_index = {gpu::PROBE_INDEX_END}, v.cells.clear(), v.cell_depth = 0;
         sync_info_counts(v);
       }},
      {"section_dependency", Sample::small, [](ProbeVolume& v) { v.svo_nodes.clear(), sync_info_counts(v); }},
      {"section_dependency", Sample::static_set, [](ProbeVolume& v) { v.leaf_header.pull_origin = 1; }},
      {"count_mismatch", Sample::small, [](ProbeVolume& v) { v.info.probe_capacity += 1; }},
      {"non_finite", Sample::small, [](ProbeVolume& v) { v.probes[0].irradiance_sh[3] = std::nanf(""); }},
      {"octree_root", Sample::small, [](ProbeVolume& v) { v.octree.clear(), v.info.octree_elements = 0; }},
      {"incomplete_cluster_used", Sample::small,
       [](ProbeVolume& v) {
         v.octree.resize(v.octree.size() + 4, 0);
         v.info.octree_elements += 4;
         v.octree[25] = static_cast<int>(v.octree.size()) - 4; // the incomplete cluster's meta index
       }},
      {"grid_octree", Sample::grid,
       [](ProbeVolume& v) {
         v.octree = {1, ~0, 0, 0, 0, 0, 0, 0, 0, 0};
         v.info.octree_elements = 10;
       }},
      {"free_not_zeroed", Sample::small, [](ProbeVolume& v) { v.octree[29] = 7; }},
      {"node_sign", Sample::small, [](ProbeVolume& v) { v.octree[28] = 5; }},
      {"meta_parent_mismatch", Sample::small, [](ProbeVolume& v) { v.octree[19] = ~3; }},
      {"octree_child_range", Sample::small, [](ProbeVolume& v) { v.octree[25] = 5; }},
      {"octree_two_parents", Sample::small, [](ProbeVolume& v) { v.octree[25] = 10; }},
      {"octree_cycle", Sample::small, [](ProbeVolume& v) { v.octree[12] = 10; }},
      {"octree_unreachable", Sample::small, [](ProbeVolume& v) { v.octree[7] = 0; }},
      {"octree_too_deep", Sample::small, [](ProbeVolume& v) { v.info.max_depth = 1; }},
      {"probe_leaf_link", Sample::small, [](ProbeVolume& v) { v.probes[~v.octree[11]].node = 13; }},
      {"probe_leaf_link", Sample::grid, [](ProbeVolume& v) { v.probes[3].node = 0; }},
      {"probe_depth_mismatch", Sample::small, [](ProbeVolume& v) { v.probes[~v.octree[11]].depth += 1; }},
      {"probe_outside_node", Sample::small, [](ProbeVolume& v) { v.probes[~v.octree[11]].position.x += 2.0f; }},
      {"free_not_zeroed", Sample::small, [](ProbeVolume& v) { v.probes[first_free_probe(v)].node = 5; }},
      {"probe_values", Sample::small, [](ProbeVolume& v) { v.probes[0].hit_fraction = -0.25f; }},
      {"probe_values", Sample::grid, [](ProbeVolume& v) { v.probes[5].backface_fraction = 1.5f; }},
      {"probe_values", Sample::small, [](ProbeVolume& v) { v.probes[first_free_probe(v)].hit_fraction = -1.0f; }},
      {"probe_values", Sample::small, [](ProbeVolume& v) { v.probes[3].pad0 = -0.0f; }},
      {"batch_link", Sample::small,
       [](ProbeVolume& v) { v.probes[probe_with_chain(v, 1)].link = ~static_cast<int>(v.surfel_batches.size() + 5); }},
      {"batch_chain_endless", Sample::small,
       [](ProbeVolume& v) {
         const std::vector<int> chain = chain_of(v, probe_with_chain(v, 2));
         v.surfel_batches[chain.back()].link = ~chain.front();
       }},
      {"batch_shared", Sample::small,
       [](ProbeVolume& v) {
         const int low = probe_with_chain(v, 1), high = probe_with_chain(v, 1, true);
         v.surfel_batches[chain_of(v, high).back()].link = ~chain_of(v, low).front();
       }},
      {"batch_owner", Sample::small,
       [](ProbeVolume& v) { v.surfel_batches[chain_of(v, probe_with_chain(v, 1)).front()].probe += 1; }},
      {"batch_count", Sample::small,
       [](ProbeVolume& v) { v.surfel_batches[chain_of(v, probe_with_chain(v, 1)).front()].count = 0; }},
      {"batch_orphan", Sample::small,
       [](ProbeVolume& v) {
         const int probe = probe_with_chain(v, 1);
         gpu::SurfelBatch& batch = v.surfel_batches[first_free_batch(v)];
         batch.link = probe + 1, batch.probe = probe, batch.count = 1;
       }},
      {"free_not_zeroed", Sample::small, [](ProbeVolume& v) { v.surfel_batches[first_free_batch(v)].count = 3; }},
      {"batch_lattice", Sample::small, [](ProbeVolume& v) { first_batch(v).first = -1; }},
      {"batch_lattice", Sample::small,
       [](ProbeVolume& v) { first_batch(v).first = v.info.surfels_per_probe - 15; }}, // count 16
      {"surfel_values", Sample::small, [](ProbeVolume& v) { first_batch(v).surfels[2].flags = 4; }},
      {"surfel_values", Sample::small,
       [](ProbeVolume& v) { first_batch(v).surfels[3].flags = gpu::SURFEL_FLAG_BACKFACE; }},
      {"surfel_values", Sample::small, [](ProbeVolume& v) { first_batch(v).surfels[4].distance = -0.5f; }},
      {"surfel_values", Sample::small, [](ProbeVolume& v) { first_batch(v).surfels[5].normal *= 2.0f; }},
      {"surfel_values", Sample::small, [](ProbeVolume& v) { first_batch(v).surfels[6].albedo.y = -0.25f; }},
      {"surfel_values", Sample::small, [](ProbeVolume& v) { first_batch(v).surfels[7].pad1 = 1.0f; }},
      {"surfel_values", Sample::small,
       [](ProbeVolume& v) { // a surfel past the batch's count was written
         gpu::SurfelBatch& second = v.surfel_batches[chain_of(v, probe_with_chain(v, 2))[1]];
         ASSERT_LT(second.count, gpu::SURFELS_PER_BATCH);
         second.surfels[gpu::SURFELS_PER_BATCH - 1].distance = 0.5f;
       }},
      {"probe_index_list", Sample::small, [](ProbeVolume& v) { std::swap(v.probe_index[0], v.probe_index[1]); }},
      {"probe_index_list", Sample::small, [](ProbeVolume& v) { v.probe_index.back() = 0; }},
      {"leaf_queue_header", Sample::small, [](ProbeVolume& v) { v.leaf_header.pull_origin = 3; }},
      {"leaf_entry_node", Sample::small, [](ProbeVolume& v) { v.leaf_entries[0].node = 2; }},
      {"leaf_entry_state", Sample::small, [](ProbeVolume& v) { v.leaf_entries[1].state = 42; }},
      {"leaf_entry_duplicate", Sample::small, [](ProbeVolume& v) { v.leaf_entries[1].node = v.leaf_entries[0].node; }},
      {"svo_index_range", Sample::small, [](ProbeVolume& v) { v.svo_leaves[0].probes[0] = 100000; }},
      {"svo_index_range", Sample::small,
       [](ProbeVolume& v) { v.svo_nodes[8] = static_cast<int>(v.svo_nodes.size()) - 4; }},
      {"svo_tree", Sample::small, [](ProbeVolume& v) { v.svo_nodes[8] = 1; }},
      {"svo_leaf_shared", Sample::small,
       [](ProbeVolume& v) {
         const std::vector<int> leaves = svo_leaf_nodes(v);
         v.svo_nodes[leaves[1]] = v.svo_nodes[leaves[0]];
       }},
      {"svo_depth", Sample::small, [](ProbeVolume& v) { v.info.svo_depth = 1; }},
      {"svo_freed_probe", Sample::small, [](ProbeVolume& v) { v.svo_leaves[0].probes[0] = first_free_probe(v); }},
      {"svo_weights", Sample::small, [](ProbeVolume& v) { v.svo_leaves[0].weights[0] += 0.5f; }},
      {"free_not_zeroed", Sample::small, [](ProbeVolume& v) { v.svo_leaves.back().probes[0] = 0; }},
      {"grid_lattice", Sample::small, // a lattice in an octree volume
       [](ProbeVolume& v) { v.grid_lattice = testing::make_sample(Sample::grid_lattice).grid_lattice; }},
      {"grid_lattice", Sample::grid_lattice, [](ProbeVolume& v) { v.grid_lattice.pop_back(); }},
      {"sky", Sample::small, [](ProbeVolume& v) { v.sky = testing::make_sample(Sample::sky).sky; }}, // no lighting
      {"sky", Sample::sky, [](ProbeVolume& v) { v.sky.pop_back(); }},
      {"sky", Sample::sky, [](ProbeVolume& v) { v.sky[10] = 0xFF800000u; }},                        // a texel of -inf
      {"sky", Sample::sky, [](ProbeVolume& v) { v.sky[3] = std::bit_cast<std::uint32_t>(20.0f); }}, // turbidity
      {"sky", Sample::sky, [](ProbeVolume& v) { v.sky[7] = 0; }}, // sun light 0 is a point light
      // Words 8, 9: point 0's probe and cells, and its reach; 10, 11: point 1's.
      {"grid_lattice", Sample::grid_lattice, [](ProbeVolume& v) { v.grid_lattice[10] = v.grid_lattice[8]; }},
      {"grid_lattice", Sample::grid_lattice, [](ProbeVolume& v) { v.grid_lattice[8] |= 1u << 24; }},
      {"grid_lattice", Sample::grid_lattice, [](ProbeVolume& v) { v.grid_lattice[8] = grid_probe_cells(8, 0); }},
      {"grid_lattice", Sample::grid_lattice, [](ProbeVolume& v) { v.grid_lattice[9] |= 1u << 31; }},
      {"grid_lattice", Sample::grid_lattice, [](ProbeVolume& v) { v.grid_lattice[4] = 0u; }}, // spacing 0
      {"grid_lattice", Sample::grid_lattice, [](ProbeVolume& v) { v.grid_lattice[3] = 3u; }}, // resolution
      {"cell_order", Sample::small, [](ProbeVolume& v) { v.cells[1].cell_index = v.cells[0].cell_index; }},
      {"cell_bounds", Sample::small, [](ProbeVolume& v) { v.cells[0].bounds_min.x += 0.5f; }},
      {"cell_root_node", Sample::small, [](ProbeVolume& v) { v.cells[0].root_node = 5; }},
      {"cell_range", Sample::small, [](ProbeVolume& v) { v.cells[0].probes.byte_offset += 1; }},
      {"cell_tracing", Sample::small,
       [](ProbeVolume& v) { v.cell_tracing.resize(v.cells.size() + 1); }}, // more: gpu_scene_test.cpp
      // Format 1.5: the cells sample's static tree is a top level over one leaf per cell.
      {"cell_tracing", Sample::cells,
       [](ProbeVolume& v) { // a face of the first cell uses a vertex of the second
         v.trace_faces[v.cell_tracing[0].trace_faces.first].vertex[0] = v.cell_tracing[1].trace_vertices.first;
       }},
      {"cell_tracing", Sample::cells,
       [](ProbeVolume& v) { // the last cell's faces start one late: the first cells' miss one
         CellRange& faces = v.cell_tracing.back().trace_faces;
         faces.first += 1, faces.byte_offset += sizeof(gpu::TraceFace);
       }},
      {"cell_tracing", Sample::cells,
       [](ProbeVolume& v) { // the dynamic object's face uses a cell's vertex
         v.trace_faces[std::size_t(v.dynamic_objects[0].first_triangle)].vertex[0] =
             v.cell_tracing[0].trace_vertices.first;
       }},
      {"non_finite", Sample::cells,
       [](ProbeVolume& v) { v.trace_vertices[v.cell_tracing.back().trace_vertices.first].y = std::nanf(""); }},
      {"trace_tree", Sample::cells,
       [](ProbeVolume& v) { // a top-level leaf holds one face fewer of its cell
         for (gpu::TraceNode& node : v.trace_nodes)
           for (std::uint32_t& word : node.child)
             if (is_leaf_word(word) && leaf_count(word) > 1) {
               word -= 1u << gpu::TRACE_LEAF_COUNT_SHIFT;
               return;
             }
         FAIL() << "no leaf of two faces or more";
       }},
      {"cell_membership", Sample::small,
       [](ProbeVolume& v) {
         v.cells[0].probes.count -= 1;
         v.cells[0].probes.byte_size -= sizeof(gpu::Probe);
       }},
      // Runtime lighting (format 1.1). Sample layout: nodes 0 (root) -> {1 leaf of triangles 0..3,
      // 2 -> {3 leaf of triangle 4, 4 leaf of triangle 5}}; lights point, spot, directional.
      {"non_finite", Sample::lighting, [](ProbeVolume& v) { v.trace_triangles[2].albedo.y = std::nanf(""); }},
      {"non_finite", Sample::lighting, [](ProbeVolume& v) { v.bvh_nodes[3].upper.x = INFINITY; }},
      {"lighting_sections", Sample::lighting, [](ProbeVolume& v) { v.lighting->triangles += 1; }},
      {"lighting_sections", Sample::lighting, [](ProbeVolume& v) { v.lighting.reset(); }},
      {"lighting_sections", Sample::lighting,
       [](ProbeVolume& v) { v.lighting->placement_rays = 31, v.lighting->rays = 7; }},
      {"lighting_sections", Sample::lighting, [](ProbeVolume& v) { v.lighting->emissive_as_lights = 0; }},
      {"lighting_values", Sample::lighting, [](ProbeVolume& v) { v.lighting->shadow_offset = 0.0f; }},
      {"lighting_values", Sample::lighting, [](ProbeVolume& v) { v.ray_directions[7].x *= 1.01f; }},
      {"lighting_values", Sample::lighting,
       [](ProbeVolume& v) { v.trace_triangles[1].normal = -v.trace_triangles[1].normal; }},
      {"lighting_values", Sample::lighting, [](ProbeVolume& v) { v.trace_triangles[0].emission.z = -1.0f; }},
      {"lighting_values", Sample::lighting, [](ProbeVolume& v) { v.punctual_lights[0].type = 3; }},
      {"lighting_values", Sample::lighting, [](ProbeVolume& v) { v.punctual_lights[1].range = -1.0f; }},
      {"lighting_values", Sample::lighting, [](ProbeVolume& v) { v.punctual_lights[2].position.x = 1.0f; }},
      {"lighting_values", Sample::lighting, [](ProbeVolume& v) { v.emitter_patches[1].pad3 = 1.0f; }},
      {"lighting_values", Sample::emitters, [](ProbeVolume& v) { v.emitter_patches[1].emitter = 2u; }},
      {"lighting_values", Sample::emitters, [](ProbeVolume& v) { v.emitter_patches[1].material = -1; }},
      {"lighting_values", Sample::emitters,
       [](ProbeVolume& v) { v.emitter_patches[1].emitter = 0u; }}, // emitter 0 with material 3 and 5
      {"lighting_flags", Sample::lighting, [](ProbeVolume& v) { v.trace_triangles[0].flags = 2u; }},
      {"lighting_flags", Sample::double_sided, [](ProbeVolume& v) { v.trace_triangles[3].flags |= 0x80000000u; }},
      {"lighting_flags", Sample::double_sided, [](ProbeVolume& v) { v.emitter_patches[1].flags = 3u; }},
      {"bvh_tree", Sample::lighting, [](ProbeVolume& v) { v.bvh_nodes[2].first = 1; }}, // node 1 reached twice
      {"bvh_tree", Sample::lighting, [](ProbeVolume& v) { v.bvh_nodes[2].first = 2; }}, // child = itself
      {"bvh_tree", Sample::lighting, [](ProbeVolume& v) { v.bvh_nodes[1].count = 5; }}, // more than 4 triangles
      {"bvh_tree", Sample::lighting, [](ProbeVolume& v) { v.bvh_nodes[4].first = 4; }}, // triangle 4 twice, 5 in none
      {"bvh_tree", Sample::lighting, [](ProbeVolume& v) { v.bvh_nodes[3].upper.x -= 0.25f; }}, // misses its triangle
      {"bvh_tree", Sample::lighting, [](ProbeVolume& v) { v.bvh_nodes[0].upper.y = 1.0f; }},   // child box sticks out
      {"bvh_tree", Sample::lighting, [](ProbeVolume& v) { make_bvh_chain(v, gpu::BVH_MAX_DEPTH); }},
      // Format 1.3: the card (object 0: node 5, triangles 6-7).
      {"dynamic_ranges", Sample::dynamic,
       [](ProbeVolume& v) { v.dynamic_objects[0].first_triangle = 5, v.dynamic_objects[0].triangle_count = 3; }},
      {"dynamic_ranges", Sample::dynamic, [](ProbeVolume& v) { v.dynamic_objects[0].gltf_node = -1; }},
      {"dynamic_ranges", Sample::dynamic,
       [](ProbeVolume& v) { v.bvh_nodes[4].first = 6; }}, // a static leaf on the card's triangle
      {"dynamic_values", Sample::dynamic,
       [](ProbeVolume& v) { v.dynamic_objects[0].upper.y = 0.25f; }}, // box misses a vertex
      {"dynamic_values", Sample::dynamic,
       [](ProbeVolume& v) { v.dynamic_objects[0].rest_rows[0].x = -1.0f; }}, // mirrored
      {"dynamic_values", Sample::dynamic,
       [](ProbeVolume& v) { v.dynamic_objects[0].rest_rows[2] = glm::vec4(0.0f); }}, // singular
      // Compact tracing (1.4). The sample's static tree: node 0 = {leaf of faces 0-3, node 1}, node 1 = {leaf 4,
      // leaf 5}; the card's tree is one leaf of faces 6-7.
      {"trace_tree", Sample::compact, [](ProbeVolume& v) { v.trace_nodes[0].child[1] = 0u; }}, // a cycle
      {"trace_tree", Sample::compact,
       [](ProbeVolume& v) { v.trace_nodes[1].child[1] = v.trace_nodes[1].child[0]; }}, // face 4 twice, 5 in none
      {"trace_tree", Sample::compact,
       [](ProbeVolume& v) { v.trace_nodes[1].child[1] = gpu::TRACE_CHILD_LEAF | (7u << 27) | 5u; }},
      {"trace_tree", Sample::compact,
       [](ProbeVolume& v) { v.trace_nodes[1].upper[0] &= 0xFFFF0000u; }}, // child 0's box misses face 4
      {"trace_tree", Sample::compact, [](ProbeVolume& v) { v.trace_trees[0].scale.y *= 0.5f; }}, // the root box shrinks
      {"trace_tree", Sample::compact,
       [](ProbeVolume&
              v) { v.trace_trees[1].root = gpu::TRACE_CHILD_LEAF | (1u << 27) | 4u; }}, // the card on static faces
      {"lighting_values", Sample::compact, [](ProbeVolume& v) { v.trace_faces[3].vertex[1] = 1000u; }},
      {"lighting_values", Sample::compact,
       [](ProbeVolume& v) { v.trace_faces[3].vertex[1] = v.trace_faces[3].vertex[0]; }}, // no area
      {"lighting_values", Sample::compact, [](ProbeVolume& v) { v.trace_faces[2].material = 77u; }},
      {"lighting_values", Sample::compact, [](ProbeVolume& v) { v.trace_materials[0].albedo.x = -0.5f; }},
      {"non_finite", Sample::compact, [](ProbeVolume& v) { v.trace_vertices[2].z = std::nanf(""); }},
      {"lighting_sections", Sample::compact, [](ProbeVolume& v) { v.trace_trees.pop_back(); }},
      {"lighting_sections", Sample::compact, [](ProbeVolume& v) { v.lighting->bvh_nodes = 1; }},
      {"dynamic_ranges", Sample::compact, [](ProbeVolume& v) { v.dynamic_objects[0].bvh_root = 2; }},
      {"dynamic_ranges", Sample::compact, [](ProbeVolume& v) { v.dynamic_objects[0].first_triangle = 5; }},
      {"dynamic_values", Sample::compact,
       [](ProbeVolume& v) { v.dynamic_objects[0].upper.y = 0.25f; }}, // box misses a vertex
  };
  return list;
}

TEST(Validate, SamplesAreValid) {
  for (Sample sample : testing::kAllSamples) {
    const ValidationReport report = validate(testing::make_sample(sample));
    EXPECT_TRUE(report.valid()) << testing::golden_name(sample) << "\n" << violations_text(report);
  }
}

TEST(Validate, EachCorruptionNamesItsInvariant) {
  for (const Corruption& corruption : corruptions()) {
    ProbeVolume volume = testing::make_sample(corruption.sample);
    corruption.corrupt(volume);
    const ValidationReport report = validate(volume);
    ASSERT_FALSE(report.valid()) << corruption.invariant;
    EXPECT_EQ(report.violations.front().invariant, corruption.invariant) << violations_text(report);
    if (std::getenv("PROBEBAKE_VERBOSE")) std::printf("%s:\n%s", corruption.invariant, violations_text(report).c_str());
  }
}

// A streaming load validates a volume whose trace nodes, faces and vertices stay in the file's mapping
// (CellFile::open): through a view, every sample and every corruption gets the same report, violation for
// violation, as the volume that holds them.
TEST(Validate, ATracingViewGetsTheSameReportAsTheVectors) {
  std::vector<std::pair<Sample, std::function<void(ProbeVolume&)>>> cases;
  for (Sample sample : testing::kAllSamples) cases.emplace_back(sample, [](ProbeVolume&) {});
  for (const Corruption& corruption : corruptions()) cases.emplace_back(corruption.sample, corruption.corrupt);
  std::size_t with_tracing = 0;
  for (const auto& [sample, corrupt] : cases) {
    ProbeVolume whole = testing::make_sample(sample);
    corrupt(whole);
    ProbeVolume stripped = whole;
    stripped.trace_nodes.clear(), stripped.trace_faces.clear(), stripped.trace_vertices.clear();
    const ValidationReport direct = validate(whole), viewed = validate(stripped, tracing_view(whole));
    EXPECT_EQ(violations_text(viewed), violations_text(direct)) << testing::sample_name(sample);
    with_tracing += whole.trace_faces.empty() ? 0 : 1;
  }
  EXPECT_GE(with_tracing, 20u); // the tracing corruptions and the samples with tracing
}

// A streaming load checks the global part at load (validate_without_cells) and each cell as it arrives
// (validate_cell_tracing): together they find a sample or corruption valid exactly when validate() does, and
// the load's check never reads the cells' own tracing: with garbage there, its report is the same.
TEST(Validate, TheCheckWithoutTheCellsAndEachCellsCheckAgreeWithTheWholeCheck) {
  std::vector<std::pair<std::string, ProbeVolume>> cases;
  for (Sample sample : testing::kAllSamples)
    cases.emplace_back(testing::sample_name(sample), testing::make_sample(sample));
  for (const Corruption& corruption : corruptions()) {
    ProbeVolume volume = testing::make_sample(corruption.sample);
    corruption.corrupt(volume);
    cases.emplace_back(corruption.invariant, std::move(volume));
  }
  std::size_t with_cells = 0, invalid = 0;
  for (const auto& [name, whole] : cases) {
    if (whole.cell_tracing.empty() || whole.cell_tracing.size() != whole.cells.size()) continue;
    ++with_cells;
    ProbeVolume garbage = whole;
    for (const CellTracing& r : garbage.cell_tracing) {
      const auto fill = [](auto& section, const CellRange& range) {
        if (std::uint64_t(range.first) + range.count <= section.size() && range.count > 0)
          std::memset(static_cast<void*>(section.data() + range.first), 0xA5, range.count * sizeof(section[0]));
      };
      fill(garbage.trace_nodes, r.trace_nodes), fill(garbage.trace_faces, r.trace_faces),
          fill(garbage.trace_vertices, r.trace_vertices);
    }
    std::vector<CellEntry> entries, garbage_entries;
    const ValidationReport global = validate_without_cells(whole, tracing_view(whole), entries);
    const ValidationReport unread = validate_without_cells(garbage, tracing_view(garbage), garbage_entries);
    EXPECT_EQ(violations_text(unread), violations_text(global)) << name;
    bool cells_valid = true;
    for (std::size_t k = 0; k < whole.cell_tracing.size() && global.valid(); ++k) {
      const CellTracingData data = cell_tracing_data(whole, k);
      EXPECT_EQ(garbage_entries[k].word, entries[k].word) << name << " cell " << k;
      cells_valid =
          validate_cell_tracing(whole, entries, k, {data.nodes, data.faces, data.vertices}).valid() && cells_valid;
    }
    const bool split_valid = global.valid() && cells_valid;
    EXPECT_EQ(split_valid, validate(whole).valid()) << name << "\n" << violations_text(validate(whole));
    invalid += split_valid ? 0 : 1;
  }
  EXPECT_GE(with_cells, 6u);
  EXPECT_GE(invalid, 5u); // the cells sample's corruptions
}

// Format 1.8: a grid with its lattice stamps 1.8 (the sample loops read it back and validate it); without the
// lattice the same grid stays 1.0.
TEST(Validate, OnlyAGridWithALatticeStamps1_8) {
  EXPECT_EQ(parse_container(write_probes(testing::make_sample(Sample::grid)), "grid").header.version_minor, 0u);
  EXPECT_EQ(parse_container(write_probes(testing::make_sample(Sample::grid_lattice)), "grid").header.version_minor,
            kGridLatticeMinor);
}

TEST(Validate, EveryModelInvariantHasACorruptionCase) {
  std::set<std::string> covered;
  for (const Corruption& corruption : corruptions()) covered.insert(corruption.invariant);
  const std::set<std::string> file_level = {
      "container",      "checksum",       "format_version", "section_flags",
      "section_layout", "trailing_bytes", "cell_checksum",  "cell_global_checksum"};
  for (const InvariantInfo& info : invariants()) {
    const std::string id = info.id;
    if (file_level.count(id))
      continue; // see corruption_test.cpp; cell_checksum, cell_global_checksum: cli_test.cpp, gpu_scene_test.cpp
    EXPECT_TRUE(covered.count(id)) << "no corruption case for " << id;
  }
}

TEST(Validate, ReportedIdsAreRegistered) {
  std::set<std::string> registered;
  for (const InvariantInfo& info : invariants()) registered.insert(info.id);
  for (const Corruption& corruption : corruptions()) {
    ProbeVolume volume = testing::make_sample(corruption.sample);
    corruption.corrupt(volume);
    for (const Violation& v : validate(volume).violations) EXPECT_TRUE(registered.count(v.invariant)) << v.invariant;
  }
}

TEST(Validate, BvhDepthLimitIsTheShadersStackSize) {
  ProbeVolume volume = testing::make_sample(Sample::lighting);
  make_bvh_chain(volume, gpu::BVH_MAX_DEPTH - 1);
  EXPECT_TRUE(validate(volume).valid()) << violations_text(validate(volume));
  make_bvh_chain(volume, gpu::BVH_MAX_DEPTH);
  const ValidationReport report = validate(volume);
  ASSERT_EQ(report.violations.size(), 2u) << violations_text(report); // the two deepest leaves
  EXPECT_EQ(format_violation(report.violations[0]), "bvh_nodes[96]: bvh_tree: depth 48 reaches BVH_MAX_DEPTH");
  EXPECT_EQ(format_violation(report.violations[1]), "bvh_nodes[95]: bvh_tree: depth 48 reaches BVH_MAX_DEPTH");
}

TEST(Validate, BvhOfAnEmptySceneIsEmpty) {
  ProbeVolume volume = testing::make_sample(Sample::lighting);
  volume.bvh_nodes.clear();
  volume.trace_triangles.clear();
  sync_info_counts(volume);
  EXPECT_TRUE(validate(volume).valid()) << violations_text(validate(volume));
  volume.trace_triangles.push_back(testing::make_sample(Sample::lighting).trace_triangles[0]);
  sync_info_counts(volume);
  const ValidationReport report = validate(volume);
  ASSERT_FALSE(report.valid());
  EXPECT_EQ(format_violation(report.violations[0]), "trace_triangles: bvh_tree: triangles but no BVH nodes");
}

TEST(Validate, MaxErrorsTruncates) {
  ProbeVolume volume = testing::make_sample(Sample::small);
  for (gpu::Probe& probe : volume.probes) probe.hit_fraction = std::nanf("");
  const ValidationReport all = validate(volume, ValidateOptions{0});
  EXPECT_EQ(all.violations.size(), volume.probes.size());
  EXPECT_FALSE(all.truncated);
  const ValidationReport three = validate(volume, ValidateOptions{3});
  EXPECT_EQ(three.violations.size(), 3u);
  EXPECT_TRUE(three.truncated);
}

TEST(Validate, JsonForm) {
  ProbeVolume volume = testing::make_sample(Sample::small);
  volume.octree[12] = 10;
  const nlohmann::json json = report_to_json(validate(volume));
  EXPECT_FALSE(json["valid"].get<bool>());
  EXPECT_TRUE(json["readable"].get<bool>());
  ASSERT_GE(json["violations"].size(), 1u);
  EXPECT_EQ(json["violations"][0]["invariant"], "octree_cycle");
  EXPECT_EQ(json["violations"][0]["section"], "octree");
  EXPECT_EQ(json["violations"][0]["index"], 10);
  EXPECT_EQ(json["violation_count"], json["violations"].size());
}

TEST(Validate, FormatViolationIsOneLine) {
  const Violation v{"octree_cycle", "octree", 10, "message"};
  EXPECT_EQ(format_violation(v), "octree[10]: octree_cycle: message");
  EXPECT_EQ(format_violation(Violation{"cell_depth", "cells", -1, "m"}), "cells: cell_depth: m");
}

} // namespace
} // namespace probebake::formats
