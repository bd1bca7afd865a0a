// Stage "gpu_scene" (probebake/bake/gpu_scene.h): the scene as the runtime lighting sections. Each value
// comes from the function the bake's own lighting uses (triangle_normal, shadow_offset, spot_cone,
// emitter_patches, lattice_directions, is_double_sided), so that the GPU works with the numbers the CPU
// bake used.
#include "probebake/bake/gpu_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <fmt/core.h>

#include "gpu_bvh.h"
#include "probebake/lighting/direct_light.h"
#include "probebake/common/parallel.h"
#include "probebake/common/lattice.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/sky_section.h"
#include "probebake/formats/trace_mesh.h"

namespace probebake::bake {
namespace {

using Clock = std::chrono::steady_clock;

// The dynamic object of every triangle (scene::Instance::dynamic_object), -1 for static ones.
std::vector<int> triangle_objects(const scene::Scene& scene) {
  std::vector<int> objects(scene.triangles.size(), -1);
  for (const scene::Instance& instance : scene.instances)
    for (std::uint32_t t = instance.first_triangle; t < instance.first_triangle + instance.triangle_count; ++t)
      objects[t] = instance.dynamic_object;
  return objects;
}

formats::TraceInputTriangle trace_triangle(const scene::Scene& scene, std::size_t t, glm::vec3 v0, glm::vec3 v1,
                                           glm::vec3 v2) {
  formats::TraceInputTriangle triangle;
  triangle.corners[0] = v0;
  triangle.corners[1] = v1;
  triangle.corners[2] = v2;
  triangle.albedo = scene.triangle_albedo[t];
  triangle.emission = scene.triangle_emission[t];
  triangle.double_sided = scene::is_double_sided(scene, t);
  return triangle;
}

// The triangles of object `object` (-1: the static ones) in scene order; an object's in its own frame
// (object_from_world). Triangles without area in float (the runtime's normal, the validator's rule) are
// left out: they are never hit.
std::vector<formats::TraceInputTriangle> scene_triangles(const scene::Scene& scene, const std::vector<int>& objects,
                                                         int object, const glm::mat4& object_from_world) {
  std::vector<formats::TraceInputTriangle> triangles;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    if (objects[t] != object) continue;
    const glm::uvec3 corners = scene.triangles[t];
    glm::vec3 v[3];
    for (int k = 0; k < 3; ++k)
      v[k] = object < 0 ? scene.positions[corners[k]]
                        : glm::vec3(object_from_world * glm::vec4(scene.positions[corners[k]], 1.0f));
    const float area = glm::length(glm::cross(v[1] - v[0], v[2] - v[0]));
    if (!(area > 0.0f) || !std::isfinite(area)) continue;
    triangles.push_back(trace_triangle(scene, t, v[0], v[1], v[2]));
  }
  return triangles;
}

// A BVH over triangles with its triangles in leaf order.
struct LeafOrderedBvh {
  detail::GpuBvh bvh;
  std::vector<formats::TraceInputTriangle> triangles;
  formats::TraceTreeInput input() const { return formats::TraceTreeInput{bvh.nodes, triangles}; }
};

LeafOrderedBvh leaf_ordered_bvh(const std::vector<formats::TraceInputTriangle>& triangles, float leaf_cost, int& depth,
                                int depth_above = 0) {
  LeafOrderedBvh out{detail::build_gpu_bvh(triangles, leaf_cost, depth_above), {}};
  out.triangles.reserve(triangles.size());
  for (std::uint32_t k : out.bvh.leaf_order) out.triangles.push_back(triangles[k]);
  depth = std::max(depth, out.bvh.depth);
  return out;
}

// Appends a BVH over `triangles` to the volume's compact tracing sections (its faces in leaf order).
int append_tree(const std::vector<formats::TraceInputTriangle>& triangles, float leaf_cost,
                formats::TraceMeshBuilder& mesh, int& depth) {
  return mesh.add_tree(leaf_ordered_bvh(triangles, leaf_cost, depth).input());
}

// Interleaved bits of a cell's grid coordinates: halving cells in this order keeps neighbours together.
std::uint32_t morton_code(int cell_index, int cell_depth) {
  const int n = formats::cells_per_axis(cell_depth);
  const int xyz[3] = {cell_index % n, (cell_index / n) % n, cell_index / (n * n)};
  std::uint32_t code = 0;
  for (int bit = 0; bit < cell_depth; ++bit)
    for (int axis = 0; axis < 3; ++axis) code |= std::uint32_t((xyz[axis] >> bit) & 1) << (3 * bit + axis);
  return code;
}

// The static tree split by streaming cell (format 1.5, formats::CellTracing): one BVH per cell over the
// triangles whose centroid lies in it, stored in cell order under a top level over the cells in Morton
// order (formats::TraceMeshBuilder::add_cell_tree). Rebuilds the volume's cells (arrange_cells) with the tracing ranges.
void append_static_cells(std::vector<formats::TraceInputTriangle> triangles, const BakeSettings& settings,
                         formats::ProbeVolume& volume, formats::TraceMeshBuilder& mesh, int& depth) {
  // One copy of the triangles at a time (a world's triangles are its largest input): the list is freed once
  // sorted into cells, and each cell's list once its tree holds them in leaf order.
  std::map<int, std::vector<formats::TraceInputTriangle>> by_cell; // sorted by cell index
  for (formats::TraceInputTriangle& t : triangles)
    by_cell[formats::cell_of_triangle(volume.info, settings.cell_depth, t.corners[0], t.corners[1], t.corners[2])]
        .push_back(std::move(t));
  std::vector<formats::TraceInputTriangle>().swap(triangles);
  std::vector<std::size_t> top_order;
  volume.cells.clear();
  for (const auto& [index, cell_triangles] : by_cell) {
    top_order.push_back(top_order.size());
    formats::Cell record;
    record.cell_index = index;
    volume.cells.push_back(record);
  }
  std::stable_sort(top_order.begin(), top_order.end(), [&](std::size_t a, std::size_t b) {
    return morton_code(volume.cells[a].cell_index, settings.cell_depth) <
           morton_code(volume.cells[b].cell_index, settings.cell_depth);
  });
  // Each cell's tree starts where the top level leaves it, so the whole tree stays under BVH_MAX_DEPTH.
  const std::vector<int> depth_above = formats::cell_top_depths(top_order);
  // The cells' trees are independent and each is built on one thread (the same tree on every run), so they
  // are built side by side.
  std::vector<std::vector<formats::TraceInputTriangle>*> cell_lists;
  for (auto& entry : by_cell) cell_lists.push_back(&entry.second);
  std::vector<LeafOrderedBvh> bvhs(cell_lists.size());
  std::vector<int> depths(cell_lists.size(), 0);
  parallel_for(cell_lists.size(), settings.threads, [&](std::size_t k) {
    bvhs[k] = leaf_ordered_bvh(*cell_lists[k], settings.trace_leaf_cost, depths[k], depth_above[k]);
    std::vector<formats::TraceInputTriangle>().swap(*cell_lists[k]);
  });
  for (const int d : depths) depth = std::max(depth, d);
  std::vector<formats::TraceTreeInput> inputs;
  for (const LeafOrderedBvh& bvh : bvhs) inputs.push_back(bvh.input());
  mesh.add_cell_tree(inputs, top_order, volume.cell_tracing);
  volume.cell_depth = settings.cell_depth;
  formats::arrange_cells(volume, settings.cell_depth); // complete records: the volume stays valid
}

// The dynamic objects (format 1.3) after the static tree: each one's triangles in its rest frame, its own
// tree and its record. Objects whose triangles all have zero area are left out (nothing to trace).
void append_dynamic_objects(const scene::Scene& scene, const std::vector<int>& objects, const BakeSettings& settings,
                            formats::ProbeVolume& volume, formats::TraceMeshBuilder& mesh, int& depth) {
  volume.dynamic_objects.clear();
  for (std::size_t o = 0; o < scene.dynamic_objects.size(); ++o) {
    const scene::DynamicObject& node = scene.dynamic_objects[o];
    const glm::mat4& rest = node.world_from_object;
    if (!(glm::determinant(glm::mat3(rest)) > 0.0f))
      throw Error(ErrorKind::input,
                  fmt::format("gpu_scene: dynamic node '{}' (nodes[{}]): its transform is singular or mirrored",
                              node.name, node.node));
    const std::vector<formats::TraceInputTriangle> triangles =
        scene_triangles(scene, objects, int(o), glm::inverse(rest));
    if (triangles.empty()) continue;
    for (const formats::TraceInputTriangle& t : triangles)
      if (settings.lighting.emissive_as_lights && t.emission != glm::vec3(0.0f))
        throw Error(ErrorKind::input,
                    fmt::format("gpu_scene: dynamic node '{}' (nodes[{}]) is emissive: emitters are static area "
                                "lights (docs/LIGHTING.md)",
                                node.name, node.node));
    gpu::DynamicObject record{};
    record.first_triangle = int(volume.trace_faces.size());
    record.bvh_root = append_tree(triangles, settings.trace_leaf_cost, mesh, depth);
    record.bvh_node_count = volume.trace_trees.back().node_count;
    record.triangle_count = int(triangles.size());
    record.lower = glm::vec3(3.4e38f);
    record.upper = glm::vec3(-3.4e38f);
    for (const formats::TraceInputTriangle& t : triangles)
      for (const glm::vec3& p : t.corners)
        record.lower = glm::min(record.lower, p), record.upper = glm::max(record.upper, p);
    record.gltf_node = node.node;
    for (int row = 0; row < 3; ++row)
      record.rest_rows[row] = glm::vec4(rest[0][row], rest[1][row], rest[2][row], rest[3][row]);
    volume.dynamic_objects.push_back(record);
  }
}

// Fields a type does not use stay zero; "no range" (<= 0) is written as 0, which range_window treats
// the same way.
gpu::PunctualLight punctual_light(const scene::Light& light, std::size_t index) {
  gpu::PunctualLight out{};
  out.intensity = light.color * light.intensity; // as DirectLighting::from_light
  if (!std::isfinite(out.intensity.x) || !std::isfinite(out.intensity.y) || !std::isfinite(out.intensity.z)) {
    throw Error(ErrorKind::input,
                fmt::format("gpu_scene: light {} ('{}'): colour x intensity is not finite", index, light.name));
  }
  if (light.type == scene::LightType::directional) {
    out.type = gpu::LIGHT_DIRECTIONAL;
    out.direction = light.direction;
    return out;
  }
  out.position = light.position;
  out.range = light.range > 0.0f ? light.range : 0.0f;
  out.type = gpu::LIGHT_POINT;
  if (light.type == scene::LightType::spot) {
    out.type = gpu::LIGHT_SPOT;
    out.direction = light.direction;
    const lighting::detail::SpotCone cone = lighting::detail::spot_cone(light);
    out.cos_outer = cone.cos_outer;
    out.spot_scale = cone.scale;
  }
  return out;
}

std::vector<gpu::EmitterPatch> gpu_patches(const scene::Scene& scene, const lighting::LightingSettings& settings) {
  std::vector<gpu::EmitterPatch> patches;
  if (!settings.emissive_as_lights) return patches; // emitters then reach the runtime through the probes
  std::vector<std::uint32_t> emitter_materials;     // emitter k's material: numbered by first patch
  for (const lighting::detail::EmitterPatch& p : lighting::detail::emitter_patches(scene, settings.emitter_samples)) {
    gpu::EmitterPatch out{};
    out.a = p.a, out.b = p.b, out.c = p.c, out.normal = p.normal, out.radiance = p.radiance;
    out.flags = p.double_sided ? gpu::EMITTER_DOUBLE_SIDED : 0u;
    const auto known = std::find(emitter_materials.begin(), emitter_materials.end(), p.material);
    out.emitter = std::uint32_t(known - emitter_materials.begin());
    if (known == emitter_materials.end()) emitter_materials.push_back(p.material);
    out.material = std::int32_t(p.material);
    patches.push_back(out);
  }
  return patches;
}

// The lighting rays (ray k of every probe), then the placement lattice (surfel k's direction).
std::vector<glm::vec4> ray_directions(const BakeSettings& settings) {
  std::vector<glm::vec4> directions;
  for (const glm::vec3& d : lattice_directions(Lattice::fibonacci, settings.lighting.rays))
    directions.emplace_back(d, 0.0f);
  for (const glm::vec3& d : lattice_directions(settings.lattice, settings.surfels_per_probe))
    directions.emplace_back(d, 0.0f);
  return directions;
}

gpu::LightingInfo lighting_info(const scene::Scene& scene, const BakeSettings& settings) {
  gpu::LightingInfo info{};
  info.sky_radiance = scene.sky.colour;
  info.rays = settings.lighting.rays;
  info.shadow_offset = lighting::detail::shadow_offset(scene);
  info.emissive_as_lights = settings.lighting.emissive_as_lights ? 1 : 0;
  info.placement_rays = settings.surfels_per_probe;
  return info; // counts: sync_info_counts
}

// The sky section (format 1.9): only for a sky with a map; a constant sky is LightingInfo::sky_radiance alone.
std::vector<std::uint32_t> sky_section(const scene::Scene& scene) {
  const sky::Sky& s = scene.sky;
  if (s.map.empty()) return {};
  gpu::SkyHeader header{};
  header.width = std::uint32_t(s.map.width);
  header.height = std::uint32_t(s.map.height);
  header.kind = s.kind;
  header.sun_light = -1;
  if (s.physical) {
    header.turbidity = s.physical->turbidity;
    header.sun_direction = glm::normalize(s.physical->sun_direction);
    header.sun_light = scene.sun_light;
  }
  return formats::sky_section_words(header, s.map.texels);
}

std::size_t section_bytes(const formats::ProbeVolume& v) {
  return sizeof(gpu::LightingInfo) + v.ray_directions.size() * sizeof(glm::vec4) +
         v.punctual_lights.size() * sizeof(gpu::PunctualLight) + v.emitter_patches.size() * sizeof(gpu::EmitterPatch) +
         v.dynamic_objects.size() * sizeof(gpu::DynamicObject) + v.sky.size() * sizeof(std::uint32_t) +
         formats::tracing_bytes(v);
}

} // namespace

RuntimeLightingReport add_runtime_lighting(const scene::Scene& scene, const BakeSettings& settings,
                                           formats::ProbeVolume& volume) {
  RuntimeLightingReport report;
  const std::vector<int> objects = triangle_objects(scene);
  const auto start = Clock::now();
  volume.bvh_nodes.clear(), volume.trace_triangles.clear();
  volume.trace_trees.clear(), volume.trace_nodes.clear(), volume.trace_faces.clear(), volume.trace_vertices.clear(),
      volume.trace_materials.clear();
  int depth = 0;
  formats::TraceMeshBuilder mesh(volume);
  append_static_cells(scene_triangles(scene, objects, -1, glm::mat4(1.0f)), settings, volume, mesh, depth); // tree 0
  append_dynamic_objects(scene, objects, settings, volume, mesh, depth);
  report.bvh_seconds = std::chrono::duration<double>(Clock::now() - start).count(); // build and compaction

  volume.punctual_lights.clear();
  for (std::size_t i = 0; i < scene.lights.size(); ++i)
    volume.punctual_lights.push_back(punctual_light(scene.lights[i], i));
  volume.emitter_patches = gpu_patches(scene, settings.lighting);
  volume.ray_directions = ray_directions(settings);
  volume.lighting = lighting_info(scene, settings);
  volume.sky = sky_section(scene);
  formats::sync_info_counts(volume);

  report.written = true;
  report.bvh_nodes = int(volume.trace_nodes.size());
  report.bvh_depth = depth;
  report.dynamic_objects = int(volume.dynamic_objects.size());
  report.triangles = int(volume.trace_faces.size());
  report.left_out_triangles = int(scene.triangles.size() - volume.trace_faces.size());
  report.vertices = int(volume.trace_vertices.size());
  report.materials = int(volume.trace_materials.size());
  report.tracing_bytes = formats::tracing_bytes(volume);
  report.lights = int(volume.punctual_lights.size());
  report.emitter_patches = int(volume.emitter_patches.size());
  report.bytes = section_bytes(volume);
  return report;
}

} // namespace probebake::bake
