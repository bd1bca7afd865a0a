// Deterministic sample volumes (see sample_volumes.h). Built with the library's own Octree and
// arrange_cells, so a change in their behaviour shows up as a golden-file difference.
#include "sample_volumes.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <span>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/formats/cells.h"
#include "probebake/formats/grid_lattice.h"
#include "probebake/formats/sky_section.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/trace_mesh.h"

namespace probebake::formats::testing {
namespace {

constexpr std::uint64_t kSampleInputHash = 0x5eed0f00d15ea5e5ull;

gpu::VolumeInfo sample_settings(int placement) {
  gpu::VolumeInfo info{};
  info.root_min = glm::vec3(-1.0f);
  info.root_size = 4.0f;
  info.placement = placement;
  info.max_depth = 3;
  info.svo_depth = placement == gpu::PLACEMENT_GRID ? 1 : 2;
  info.lattice = gpu::LATTICE_FIBONACCI;
  info.surfels_per_probe = 32;
  info.split_low = 0.125f;
  info.split_high = 0.625f;
  info.grid_resolution = placement == gpu::PLACEMENT_GRID ? 2 : 0;
  return info;
}

void fill_probe_data(gpu::Probe& probe, int index) {
  probe.hit_fraction = 0.25f + 0.015625f * static_cast<float>(index % 16);
  probe.backface_fraction = 0.0625f * static_cast<float>(index % 4);
  for (int k = 0; k < gpu::PROBE_SH_FLOATS; ++k) {
    probe.irradiance_sh[k] = 0.0078125f * static_cast<float>(k + 1) + 0.001953125f * static_cast<float>(index);
  }
}

void fill_batch(gpu::SurfelBatch& batch, const gpu::Probe& probe, int index_in_chain, int probe_index) {
  batch.count = index_in_chain == 0 ? gpu::SURFELS_PER_BATCH : 1 + probe_index % 7;
  batch.first = gpu::SURFELS_PER_BATCH * index_in_chain;
  for (int s = 0; s < batch.count; ++s) {
    gpu::Surfel& surfel = batch.surfels[s];
    const float f = static_cast<float>(s);
    surfel.position = probe.position + glm::vec3(0.0625f * f, -0.03125f * f, 0.015625f);
    surfel.distance = 0.125f * (f + 1.0f);
    surfel.normal = glm::vec3(s % 3 == 0 ? 1.0f : 0.0f, s % 3 == 1 ? 1.0f : 0.0f, s % 3 == 2 ? 1.0f : 0.0f);
    surfel.flags = gpu::SURFEL_FLAG_HIT | (s % 5 == 0 ? gpu::SURFEL_FLAG_BACKFACE : 0u);
    surfel.albedo = glm::vec3(0.5f, 0.25f, 0.75f);
    surfel.radiance = glm::vec3(0.001953125f * f, 0.5f, 0.25f);
  }
}

std::vector<int> leaves_of(const ProbeVolume& volume) {
  std::vector<int> leaves;
  for_each_leaf(volume, [&](const NodeCube& leaf) { leaves.push_back(leaf.node); });
  return leaves;
}

// Root split; children 0 (node 2), 7 (node 9) and 5 (node 7) split again; a cluster allocated for node 6
// and collapsed again leaves a free cluster between allocated ones.
void build_tree(Octree& tree) {
  tree.reserve_clusters(5);
  const int root_children = tree.split(gpu::OCTREE_ROOT);
  tree.split(child_node(root_children, 0));
  tree.split(child_node(root_children, 7));
  tree.split(child_node(root_children, 4));
  tree.split(child_node(root_children, 5));
  tree.collapse(child_node(root_children, 4));
}

void build_probes(Octree& tree, bool with_surfels) {
  const std::vector<int> leaves = leaves_of(tree.volume());
  tree.reserve_probes(static_cast<int>(leaves.size()) + 1);
  if (with_surfels) tree.reserve_batches(44);
  std::vector<int> probes;
  for (int leaf : leaves) {
    const int probe = tree.place_probe(leaf);
    fill_probe_data(tree.volume().probes[probe], probe);
    probes.push_back(probe);
    if (!with_surfels) continue;
    for (int b = 0; b < 1 + probe % 2; ++b) {
      const int batch = tree.append_surfel_batch(probe);
      fill_batch(tree.volume().surfel_batches[batch], tree.volume().probes[probe], b, probe);
    }
  }
  // Free a few probes (and their surfels) to leave holes and probe-less leaves.
  for (int i : {1, 8, 17, 26}) tree.free_probe(probes[i]);
}

void build_leaf_queue(ProbeVolume& volume) {
  const std::vector<int> leaves = leaves_of(volume);
  init_leaf_queue(volume, 32);
  volume.leaf_header.pull_origin = 1;
  for (int e = 0; e < 6; ++e) volume.leaf_entries[e] = gpu::LeafEntry{leaves[e], gpu::LEAF_L2_LIGHT};
  for (int e = 0; e < 3; ++e) volume.leaf_entries[32 + e] = gpu::LeafEntry{leaves[10 + e], gpu::LEAF_L1_PLACE_SURFELS};
  volume.leaf_header.count[0] = 6;
  volume.leaf_header.count[1] = 3;
}

// Payload for a voxel: the k nearest allocated probes (ties by index) with exact binary weights.
gpu::SvoLeaf nearest_probes_payload(const ProbeVolume& volume, glm::vec3 centre, int k) {
  std::vector<std::pair<float, int>> candidates;
  for (std::size_t p = 0; p < volume.probes.size(); ++p) {
    if (volume.probes[p].link == 0) continue;
    const glm::vec3 d = volume.probes[p].position - centre;
    candidates.emplace_back(d.x * d.x + d.y * d.y + d.z * d.z, static_cast<int>(p));
  }
  std::sort(candidates.begin(), candidates.end());
  static constexpr float kWeights[4][4] = {
      {1.0f, 0, 0, 0}, {0.5f, 0.5f, 0, 0}, {0.5f, 0.25f, 0.25f, 0}, {0.25f, 0.25f, 0.25f, 0.25f}};
  gpu::SvoLeaf leaf{glm::ivec4(-1), glm::vec4(0.0f)};
  k = std::min<int>(k, static_cast<int>(candidates.size()));
  for (int slot = 0; slot < k; ++slot) {
    leaf.probes[slot] = candidates[slot].second;
    leaf.weights[slot] = kWeights[k - 1][slot];
  }
  return leaf;
}

// SVO of depth 2 (depth 1 for the grid): which voxels are split, filled or empty is a fixed pattern.
void build_svo(ProbeVolume& volume) {
  const bool grid = volume.info.placement == gpu::PLACEMENT_GRID;
  volume.svo_nodes.assign(9, 0);
  volume.svo_nodes[0] = 1;
  const NodeCube root = root_cube(volume.info);
  auto add_leaf = [&](int node, const NodeCube& cube) {
    const int k = 1 + static_cast<int>(volume.svo_leaves.size()) % 4;
    volume.svo_leaves.push_back(nearest_probes_payload(volume, cube.centre(), grid ? 1 : k));
    volume.svo_nodes[node] = ~static_cast<int>(volume.svo_leaves.size() - 1);
  };
  for (int octant = 0; octant < 8; ++octant) {
    const NodeCube cube = child_cube(root, octant);
    if (grid || octant == 1 || octant == 2 || octant == 4) {
      add_leaf(1 + octant, cube);
    } else if (octant == 0 || octant == 7) {
      const int first = static_cast<int>(volume.svo_nodes.size());
      volume.svo_nodes[1 + octant] = first;
      volume.svo_nodes.resize(volume.svo_nodes.size() + 8, 0);
      for (int sub = 0; sub < 8; sub += 2) add_leaf(first + sub, child_cube(cube, sub));
    }
  }
  if (!grid) volume.svo_leaves.push_back(gpu::SvoLeaf{glm::ivec4(-1), glm::vec4(0.0f)}); // an unused payload
}

ProbeVolume make_octree_sample(bool with_surfels) {
  ProbeVolume volume = make_empty_volume(sample_settings(gpu::PLACEMENT_OCTREE));
  Octree tree(volume);
  build_tree(tree);
  build_probes(tree, with_surfels);
  if (with_surfels) build_leaf_queue(volume);
  build_svo(volume);
  return volume;
}

ProbeVolume make_grid_sample() {
  ProbeVolume volume = make_empty_volume(sample_settings(gpu::PLACEMENT_GRID));
  const float step = volume.info.root_size / 2.0f;
  for (int i = 0; i < 8; ++i) {
    gpu::Probe probe{};
    probe.position = volume.info.root_min + step * glm::vec3(0.5f + static_cast<float>(i & 1),
                                                             0.5f + static_cast<float>((i >> 1) & 1),
                                                             0.5f + static_cast<float>(i >> 2));
    probe.link = ~gpu::PROBE_NO_SURFELS;
    probe.node = -1;
    fill_probe_data(probe, i);
    volume.probes.push_back(probe);
  }
  build_svo(volume);
  return volume;
}

// The grid sample's 2^3 lattice: probe i at point i, each point serving the one cell, no surface within reach.
void add_grid_lattice(ProbeVolume& v) {
  const glm::vec3 lo = v.info.root_min;
  std::vector<gpu::GridPoint> points;
  const std::uint32_t no_surface = grid_reach_word({2.0f, 2.0f, 2.0f, 2.0f, 2.0f, 2.0f});
  for (std::uint32_t i = 0; i < 8; ++i) points.push_back({grid_probe_cells(int(i), 1u << (7 - i)), no_surface});
  v.grid_lattice = grid_lattice_words(grid_lattice_frame(lo, lo + glm::vec3(v.info.root_size), 2), points);
}

gpu::TraceTriangle trace_triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c, int source,
                                  glm::vec3 emission = glm::vec3(0.0f)) {
  gpu::TraceTriangle t{};
  t.v0 = a;
  t.edge1 = b - a;
  t.edge2 = c - a;
  t.source = source;
  const glm::vec3 n = glm::cross(t.edge1, t.edge2); // axis-aligned in the sample: the division is exact
  t.normal = n / std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)});
  t.albedo = glm::vec3(0.5f, 0.25f, 0.75f);
  t.emission = emission;
  return t;
}

// Floor (2 triangles) and wall (2) in one leaf, an emissive ceiling triangle and a small block triangle
// in one leaf each: root -> {leaf 1, inner 2 -> {leaf 3, leaf 4}}. Boxes are the exact vertex bounds.
void build_sample_bvh(ProbeVolume& v) {
  const glm::vec3 o(0.0f);
  v.trace_triangles = {trace_triangle(o, {0, 0, 2}, {2, 0, 0}, 0),
                       trace_triangle({2, 0, 0}, {0, 0, 2}, {2, 0, 2}, 1),
                       trace_triangle(o, {0, 2, 0}, {0, 0, 2}, 2),
                       trace_triangle({0, 2, 0}, {0, 2, 2}, {0, 0, 2}, 3),
                       trace_triangle({0.5f, 2, 0.5f}, {1.5f, 2, 0.5f}, {0.5f, 2, 1.5f}, 5, glm::vec3(4.0f)),
                       trace_triangle({1, 0, 1}, {1.5f, 0, 1}, {1, 0.5f, 1}, 4)};
  v.bvh_nodes = {{{}, 1, {}, 0}, {{}, 0, {}, 4}, {{}, 3, {}, 0}, {{}, 4, {}, 1}, {{}, 5, {}, 1}};
  for (int node : {4, 3, 1, 2, 0}) { // children before parents
    gpu::BvhNode& n = v.bvh_nodes[node];
    n.lower = glm::vec3(1e30f), n.upper = glm::vec3(-1e30f);
    const auto extend = [&](glm::vec3 p) { n.lower = glm::min(n.lower, p), n.upper = glm::max(n.upper, p); };
    if (n.count == 0) {
      for (int c : {n.first, n.first + 1}) extend(v.bvh_nodes[c].lower), extend(v.bvh_nodes[c].upper);
    }
    for (int t = n.first; t < n.first + n.count; ++t) {
      const gpu::TraceTriangle& tri = v.trace_triangles[t];
      extend(tri.v0), extend(tri.v0 + tri.edge1), extend(tri.v0 + tri.edge2);
    }
  }
}

gpu::PunctualLight punctual_light(int type, glm::vec3 position, glm::vec3 direction, glm::vec3 intensity) {
  gpu::PunctualLight l{};
  l.type = type;
  l.position = position;
  l.direction = direction;
  l.intensity = intensity;
  return l;
}

// Six axis directions for lighting, then 32 placement directions (a, b, c) / d of Pythagorean quadruples.
std::vector<glm::vec4> sample_directions() {
  std::vector<glm::vec4> d = {{1, 0, 0, 0}, {-1, 0, 0, 0}, {0, 1, 0, 0}, {0, -1, 0, 0}, {0, 0, 1, 0}, {0, 0, -1, 0}};
  const glm::vec3 quadruples[] = {{1, 2, 2}, {2, 1, 2}, {2, 2, 1}, {2, 3, 6}};
  const float lengths[] = {3, 3, 3, 7};
  for (int q = 0; q < 4; ++q) {
    for (int signs = 0; signs < 8; ++signs) {
      const glm::vec3 s(signs & 1 ? -1.0f : 1.0f, signs & 2 ? -1.0f : 1.0f, signs & 4 ? -1.0f : 1.0f);
      d.push_back(glm::vec4(s * quadruples[q] / lengths[q], 0.0f));
    }
  }
  return d;
}

void add_sample_lighting(ProbeVolume& v) {
  gpu::LightingInfo info{};
  info.sky_radiance = glm::vec3(0.25f, 0.5f, 1.0f);
  info.rays = 6;
  info.shadow_offset = 0.00048828125f;
  info.emissive_as_lights = 1;
  info.placement_rays = v.info.surfels_per_probe; // 32
  v.lighting = info;
  v.ray_directions = sample_directions();
  build_sample_bvh(v);
  v.punctual_lights = {punctual_light(gpu::LIGHT_POINT, {1, 1.5f, 1}, {}, glm::vec3(10.0f)),
                       punctual_light(gpu::LIGHT_SPOT, {1, 1.875f, 1}, {0, -1, 0}, {5, 4, 3}),
                       punctual_light(gpu::LIGHT_DIRECTIONAL, {}, {0, -0.6f, -0.8f}, glm::vec3(1.0f))};
  v.punctual_lights[1].range = 4.0f;
  v.punctual_lights[1].cos_outer = 0.75f;
  v.punctual_lights[1].spot_scale = 4.0f; // 1 / (cos inner - cos outer) = 1 / (1 - 0.75)
  const glm::vec3 a(0.5f, 2, 0.5f), b(1.5f, 2, 0.5f), c(0.5f, 2, 1.5f), ab = 0.5f * (a + b);
  v.emitter_patches = {{a, 0, ab, 0, c, 0, {0, -1, 0}, 0, glm::vec3(4.0f), 0},
                       {ab, 0, b, 0, c, 0, {0, -1, 0}, 0, glm::vec3(4.0f), 0}};
}

// Format 1.2: the wall (trace triangles 2, 3) and the emissive ceiling triangle (4) with its two patches.
void mark_double_sided(ProbeVolume& v) {
  for (int t : {2, 3, 4}) v.trace_triangles[t].flags = gpu::TRIANGLE_DOUBLE_SIDED;
  for (gpu::EmitterPatch& patch : v.emitter_patches) patch.flags = gpu::EMITTER_DOUBLE_SIDED;
}

// Format 1.3: a card of two triangles in its own frame (x, y in [0, 0.5]), one leaf node after the static
// tree, at rest 1 m above the floor's centre.
void add_sample_object(ProbeVolume& v) {
  gpu::DynamicObject o{};
  o.first_triangle = int(v.trace_triangles.size());
  o.bvh_root = int(v.bvh_nodes.size());
  v.trace_triangles.push_back(trace_triangle({0, 0, 0}, {0.5f, 0, 0}, {0, 0.5f, 0}, 6));
  v.trace_triangles.push_back(trace_triangle({0.5f, 0, 0}, {0.5f, 0.5f, 0}, {0, 0.5f, 0}, 7));
  v.bvh_nodes.push_back({{0, 0, 0}, o.first_triangle, {0.5f, 0.5f, 0}, 2});
  o.bvh_node_count = 1;
  o.triangle_count = 2;
  o.lower = glm::vec3(0.0f);
  o.upper = glm::vec3(0.5f, 0.5f, 0.0f);
  o.gltf_node = 3;
  o.rest_rows[0] = glm::vec4(1, 0, 0, 1);
  o.rest_rows[1] = glm::vec4(0, 1, 0, 1);
  o.rest_rows[2] = glm::vec4(0, 0, 1, 1);
  v.dynamic_objects = {o};
}

TraceInputTriangle input_triangle(const gpu::TraceTriangle& t) {
  TraceInputTriangle in;
  in.corners[0] = t.v0, in.corners[1] = t.v0 + t.edge1, in.corners[2] = t.v0 + t.edge2;
  in.albedo = t.albedo, in.emission = t.emission;
  in.double_sided = (t.flags & gpu::TRIANGLE_DOUBLE_SIDED) != 0u;
  return in;
}

// Format 1.5: the float sections traced as a static tree split by the cells of depth 1 (each cell's faces
// in one leaf, the cells in index order, which is their Morton order at depth 1) and the object's tree.
void split_tracing_by_cell(ProbeVolume& v) {
  const gpu::DynamicObject object = v.dynamic_objects.at(0);
  std::map<int, std::vector<TraceInputTriangle>> by_cell;
  for (int t = 0; t < object.first_triangle; ++t) {
    const TraceInputTriangle in = input_triangle(v.trace_triangles[std::size_t(t)]);
    by_cell[cell_of_triangle(v.info, 1, in.corners[0], in.corners[1], in.corners[2])].push_back(in);
  }
  v.cells.clear();
  std::vector<TraceInputTriangle> card;
  for (int t = object.first_triangle; t < object.first_triangle + object.triangle_count; ++t)
    card.push_back(input_triangle(v.trace_triangles[std::size_t(t)]));
  v.bvh_nodes.clear(), v.trace_triangles.clear();
  std::vector<gpu::BvhNode> leaves; // one per cell, then the card's
  for (const auto& [index, triangles] : by_cell) leaves.push_back({{}, 0, {}, int(triangles.size())});
  std::vector<TraceTreeInput> cells;
  std::vector<std::size_t> order;
  std::size_t k = 0;
  for (const auto& [index, triangles] : by_cell) {
    cells.push_back({std::span(&leaves[k], 1), triangles});
    order.push_back(k++);
    Cell record;
    record.cell_index = index;
    v.cells.push_back(record);
  }
  TraceMeshBuilder mesh(v);
  mesh.add_cell_tree(cells, order, v.cell_tracing);
  const gpu::BvhNode card_leaf{{}, 0, {}, int(card.size())};
  gpu::DynamicObject& o = v.dynamic_objects[0];
  o.first_triangle = int(v.trace_faces.size());
  o.bvh_root = mesh.add_tree({std::span(&card_leaf, 1), card});
  o.bvh_node_count = v.trace_trees.back().node_count;
  v.cell_depth = 1;
}

// A 4 x 2 physical sky (texel k: radiance k, k + 0.5, 2k) whose sun is not among the lights.
void add_sample_sky(ProbeVolume& v) {
  gpu::SkyHeader header{};
  header.width = 4;
  header.height = 2;
  header.kind = gpu::SKY_KIND_PHYSICAL;
  header.turbidity = 2.5f;
  header.sun_direction = glm::vec3(0.0f, 1.0f, 0.0f);
  header.sun_light = -1;
  std::vector<glm::vec3> texels;
  for (int k = 0; k < 8; ++k) texels.emplace_back(float(k), float(k) + 0.5f, 2.0f * float(k));
  v.sky = sky_section_words(header, texels);
}

} // namespace

ProbeVolume make_sample(Sample sample) {
  const bool grid = sample == Sample::grid || sample == Sample::grid_lattice;
  ProbeVolume volume = grid ? make_grid_sample() : make_octree_sample(sample == Sample::small);
  if (sample == Sample::grid_lattice) add_grid_lattice(volume);
  const bool compact = sample == Sample::compact || sample == Sample::cells;
  const bool lit = sample == Sample::lighting || sample == Sample::sky || sample == Sample::double_sided ||
                   sample == Sample::dynamic || sample == Sample::emitters || compact;
  if (lit) add_sample_lighting(volume);
  if (sample == Sample::double_sided || compact) mark_double_sided(volume);
  if (sample == Sample::dynamic || compact) add_sample_object(volume);
  if (sample == Sample::cells) split_tracing_by_cell(volume);
  if (sample == Sample::sky) add_sample_sky(volume);
  if (sample == Sample::emitters) {
    volume.emitter_patches[0].material = 3;
    volume.emitter_patches[1].emitter = 1, volume.emitter_patches[1].material = 5;
  }
  sync_info_counts(volume);
  if (sample == Sample::compact) upgrade_tracing(volume);
  arrange_cells(volume, 1); // also rebuilds the probe index
  volume.input_hash = kSampleInputHash;
  return volume;
}

namespace {

// Each sample's name (test parameters, messages) and its golden file under tests/data/golden/.
struct SampleNames {
  Sample sample;
  const char* name;
  const char* golden;
};
constexpr SampleNames kSampleNames[] = {
    {Sample::small, "small", "v1_0_small.probes"},
    {Sample::static_set, "static", "v1_0_static.probes"},
    {Sample::grid, "grid", "v1_0_grid.probes"},
    {Sample::lighting, "lighting", "v1_1_lighting.probes"},
    {Sample::double_sided, "double_sided", "v1_2_double_sided.probes"},
    {Sample::dynamic, "dynamic", "v1_3_dynamic.probes"},
    {Sample::compact, "compact", "v1_4_compact.probes"},
    {Sample::cells, "cells", "v1_7_cells.probes"},
    {Sample::grid_lattice, "grid_lattice", "v1_8_grid_lattice.probes"},
    {Sample::sky, "sky", "v1_9_sky.probes"},
    {Sample::emitters, "emitters", "v1_10_emitters.probes"},
};
static_assert(std::size(kSampleNames) == std::size(kAllSamples), "a name for every sample");

const SampleNames* names_of(Sample sample) {
  for (const SampleNames& names : kSampleNames)
    if (names.sample == sample) return &names;
  return nullptr;
}

} // namespace

const char* sample_name(Sample sample) {
  const SampleNames* names = names_of(sample);
  return names != nullptr ? names->name : "";
}

const char* golden_name(Sample sample) {
  const SampleNames* names = names_of(sample);
  return names != nullptr ? names->golden : "";
}

} // namespace probebake::formats::testing
