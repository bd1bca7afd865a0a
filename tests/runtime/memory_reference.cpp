// The CPU side of the memory update tests (memory_reference.h).
#include "memory_reference.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "probebake/bake/bake.h"
#include "probebake/dynamic/animation.h"
#include "probebake/formats/trace_mesh.h"
#include "probebake/formats/validate.h"
#include "probebake/samples/scenes.h"
#include "probebake/scene/scene.h"

namespace probebake::test {

// Cornell box at max depth 1 with surfel batches (so the batch pool is exercised) and the lighting sections.
namespace {

formats::ProbeVolume bake_shallow_cornell() {
  bake::BakeSettings s = small_bake_settings();
  s.max_depth = 1;
  s.surfels_per_probe = 48;
  s.lighting.rays = 32;
  s.store_surfels = true;
  return bake_with(samples::cornell(), "cornell-d1", s);
}

} // namespace

const formats::ProbeVolume& shallow_cornell() {
  static const formats::ProbeVolume v = bake_shallow_cornell();
  return v;
}

// ---- The CPU measure in the shaders' arithmetic (bvh_trace.glsl, octree.glsl), every triangle tested ----

namespace {

float ray_triangle(const formats::TraceFaceGeometry& tri, glm::vec3 origin, glm::vec3 dir) {
  const glm::vec3 p = glm::cross(dir, tri.edge2);
  const float det = glm::dot(tri.edge1, p);
  if (det == 0.0f) return -1.0f;
  const float inv = 1.0f / det;
  const glm::vec3 s = origin - tri.v0;
  const float u = glm::dot(s, p) * inv;
  if (u < 0.0f || u > 1.0f) return -1.0f;
  const glm::vec3 q = glm::cross(s, tri.edge1);
  const float v = glm::dot(dir, q) * inv;
  if (v < 0.0f || u + v > 1.0f) return -1.0f;
  return glm::dot(tri.edge2, q) * inv;
}

float exit_distance(const formats::NodeCube& cube, glm::vec3 inside, glm::vec3 dir) {
  float t = 3.4e38f;
  for (int a = 0; a < 3; ++a) {
    if (dir[a] > 0.0f)
      t = std::min(t, (cube.min[a] + cube.size - inside[a]) / dir[a]);
    else if (dir[a] < 0.0f)
      t = std::min(t, (cube.min[a] - inside[a]) / dir[a]);
  }
  return std::max(t, 0.0f);
}

} // namespace

// The nearest hit of one ray: static triangles as stored (world space), each dynamic object's in object
// space after moving the ray there with the inverse of its pose, as bvh_trace.glsl does (the direction not
// normalised, so t is the same in both spaces). For translations the inverse is exact, so both sides agree
// bit for bit.

NearestHit nearest_hit(const formats::ProbeVolume& v, std::span<const glm::mat4> poses, glm::vec3 origin,
                       glm::vec3 dir) {
  NearestHit best;
  const auto test = [&](std::size_t first, std::size_t count, glm::vec3 o, glm::vec3 d, const glm::mat4* pose) {
    for (std::size_t t = first; t < first + count; ++t) {
      const formats::TraceFaceGeometry face = formats::face_geometry(v, t);
      const float hit = ray_triangle(face, o, d);
      if (hit >= 0.0f && hit <= best.t && (best.triangle < 0 || hit < best.t)) {
        best.t = hit;
        best.triangle = int(t);
        const glm::vec3 n = face.normal;
        best.normal = pose ? glm::normalize(glm::transpose(glm::inverse(glm::mat3(*pose))) * n) : n;
      }
    }
  };
  const std::size_t statics =
      v.dynamic_objects.empty() ? v.trace_faces.size() : std::size_t(v.dynamic_objects[0].first_triangle);
  test(0, statics, origin, dir, nullptr);
  for (std::size_t o = 0; o < v.dynamic_objects.size(); ++o) {
    const glm::mat4 inverse = glm::inverse(poses[o]);
    const gpu::DynamicObject& object = v.dynamic_objects[o];
    test(std::size_t(object.first_triangle), std::size_t(object.triangle_count),
         glm::vec3(inverse * glm::vec4(origin, 1.0f)), glm::vec3(inverse * glm::vec4(dir, 0.0f)), &poses[o]);
  }
  return best;
}

dynamic::LeafTrace measure(const formats::ProbeVolume& v, const formats::NodeCube& cube,
                           std::span<const glm::mat4> poses) {
  const glm::vec3 centre = cube.centre();
  const int first = v.lighting->rays, rays = v.lighting->placement_rays;
  int in_cube = 0, hits = 0, backface = 0;
  for (int r = 0; r < rays; ++r) {
    const glm::vec3 dir = glm::vec3(v.ray_directions[std::size_t(first + r)]);
    const NearestHit hit = nearest_hit(v, poses, centre, dir);
    if (hit.triangle < 0) continue;
    ++hits;
    const bool double_sided = (v.trace_faces[std::size_t(hit.triangle)].material & gpu::TRACE_FACE_DOUBLE_SIDED) != 0u;
    if (glm::dot(hit.normal, dir) > 0.0f && !double_sided) ++backface;
    if (hit.t <= exit_distance(cube, centre, dir)) ++in_cube;
  }
  return {rays > 0 ? float(in_cube) / float(rays) : 0.0f, hits > 0 ? float(backface) / float(hits) : 0.0f};
}

// ---- Canonical form of a tree and its queue ------------------------------------------------------------

// Octants from the root ("" = root, "37" = child 7 of child 3), or nullopt for a node that is not live.
std::optional<std::string> path_of(const formats::ProbeVolume& v, int node) {
  std::string path;
  for (int steps = 0; node != 0; ++steps) {
    if (node < 0 || std::size_t(node) >= v.octree.size() || !formats::is_node_index(node) ||
        steps > gpu::OCTREE_MAX_DEPTH)
      return std::nullopt;
    const int meta = formats::cluster_meta_of(node);
    if (v.octree[std::size_t(meta)] >= 0) return std::nullopt;
    path.insert(path.begin(), char('0' + formats::octant_of(node)));
    node = ~v.octree[std::size_t(meta)];
  }
  return path;
}

Canonical canonical(const formats::ProbeVolume& v) {
  Canonical c;
  formats::for_each_leaf(v, [&](const formats::NodeCube& leaf) {
    const int value = v.octree[std::size_t(leaf.node)];
    std::tuple<bool, float, float, float, int> entry{value < 0, 0.0f, 0.0f, 0.0f, leaf.depth};
    if (value < 0) {
      const gpu::Probe& p = v.probes[std::size_t(~value)];
      entry = {true, p.position.x, p.position.y, p.position.z, p.depth};
    }
    c.leaves.emplace(*path_of(v, leaf.node), entry);
  });
  const int capacity = v.leaf_header.segment_capacity;
  for (int s = 0; s < 3; ++s)
    for (int e = 0; e < v.leaf_header.count[s]; ++e) {
      const gpu::LeafEntry& entry = v.leaf_entries[std::size_t(s * capacity + e)];
      c.segments[std::size_t(s)].emplace(path_of(v, entry.node).value_or("dead " + std::to_string(entry.node)),
                                         entry.state);
    }
  c.pull_origin = v.leaf_header.pull_origin;
  for (const gpu::Probe& p : v.probes) c.probes += p.link != 0 ? 1 : 0;
  for (const gpu::SurfelBatch& b : v.surfel_batches) c.batches += b.link != 0 ? 1 : 0;
  for (std::size_t m = 1; m + 8 < v.octree.size(); m += 9) c.clusters += v.octree[m] < 0 ? 1 : 0;
  return c;
}

// Names the first difference between two canonical trees, or "" when they are equal.
std::string first_difference(const Canonical& gpu, const Canonical& cpu) {
  if (gpu.pull_origin != cpu.pull_origin)
    return "pull origin " + std::to_string(gpu.pull_origin) + " vs " + std::to_string(cpu.pull_origin);
  for (const auto& [path, leaf] : cpu.leaves) {
    const auto found = gpu.leaves.find(path);
    if (found == gpu.leaves.end()) return "leaf '" + path + "' only on the CPU";
    if (found->second != leaf) {
      auto text = [](const std::tuple<bool, float, float, float, int>& l) {
        char buffer[160];
        std::snprintf(buffer, sizeof(buffer), "(probe %d at %.9g %.9g %.9g depth %d)", int(std::get<0>(l)),
                      double(std::get<1>(l)), double(std::get<2>(l)), double(std::get<3>(l)), std::get<4>(l));
        return std::string(buffer);
      };
      return "leaf '" + path + "' differs: " + text(found->second) + " vs " + text(leaf);
    }
  }
  for (const auto& [path, leaf] : gpu.leaves)
    if (!cpu.leaves.count(path)) return "leaf '" + path + "' only on the GPU";
  for (int s = 0; s < 3; ++s)
    if (gpu.segments[std::size_t(s)] != cpu.segments[std::size_t(s)]) {
      for (const auto& [path, state] : cpu.segments[std::size_t(s)]) {
        const auto found = gpu.segments[std::size_t(s)].find(path);
        if (found == gpu.segments[std::size_t(s)].end())
          return "segment " + std::to_string(s) + ": '" + path + "' (state " + std::to_string(state) +
                 ") only on the CPU";
        if (found->second != state)
          return "segment " + std::to_string(s) + ": '" + path + "' state " + std::to_string(found->second) + " vs " +
                 std::to_string(state);
      }
      for (const auto& [path, state] : gpu.segments[std::size_t(s)])
        if (!cpu.segments[std::size_t(s)].count(path))
          return "segment " + std::to_string(s) + ": '" + path + "' (state " + std::to_string(state) +
                 ") only on the GPU";
      return "segment " + std::to_string(s) + ": entries differ";
    }
  if (gpu.probes != cpu.probes || gpu.batches != cpu.batches || gpu.clusters != cpu.clusters)
    return "pool use (probes, batches, clusters) " + std::to_string(gpu.probes) + "/" + std::to_string(gpu.batches) +
           "/" + std::to_string(gpu.clusters) + " vs " + std::to_string(cpu.probes) + "/" +
           std::to_string(cpu.batches) + "/" + std::to_string(cpu.clusters);
  return "";
}

// ---- The two sides, driven by the same frames --------------------------------------------------------------

runtime::Box root_box(const formats::ProbeVolume& v) {
  return {v.info.root_min, v.info.root_min + glm::vec3(v.info.root_size)};
}

Cpu::Cpu(const formats::ProbeVolume& start)
    : volume(start), tree(volume, formats::Octree::Growth::fixed), update(tree) {
  for (const gpu::DynamicObject& o : volume.dynamic_objects) poses.push_back(dynamic::rest_pose(o));
}

runtime::Box world_box(const gpu::DynamicObject& object, const glm::mat4& pose) {
  const dynamic::WorldBox box = dynamic::world_box(object, pose);
  return {box.min, box.max};
}

dynamic::TreeFrameStats Cpu::frame(const Step& step, std::span<const runtime::ObjectPose> moves) {
  if (step.max_depth) volume.info.max_depth = *step.max_depth;
  std::vector<dynamic::Box> boxes;
  for (const runtime::Box& b : step.boxes) boxes.push_back({b.min, b.max});
  for (const runtime::ObjectPose& move : moves) { // the runtime's rule: old and new world boxes, in this order
    const auto o = std::size_t(move.object);
    if (poses[o] == move.world_from_object) continue;
    const runtime::Box before = world_box(volume.dynamic_objects[o], poses[o]);
    const runtime::Box after = world_box(volume.dynamic_objects[o], move.world_from_object);
    boxes.push_back({glm::min(before.min, after.min), glm::max(before.max, after.max)});
    poses[o] = move.world_from_object;
  }
  return update.run_frame(boxes,
                          [this](const formats::NodeCube& cube, glm::vec3) { return measure(volume, cube, poses); });
}

runtime::UploadOptions dynamic_options() {
  runtime::UploadOptions o;
  o.memory_update = true;
  o.pools.free_clusters = 80;
  o.pools.free_probes = 700;
  return o;
}

void expect_same_stats(const runtime::MemoryUpdateStats& gpu, const dynamic::TreeFrameStats& cpu, int frame) {
  for (int s = 0; s < gpu::LEAF_STATE_COUNT; ++s)
    EXPECT_EQ(gpu.processed[std::size_t(s)], cpu.processed[std::size_t(s)]) << "frame " << frame << " state " << s;
  EXPECT_EQ(gpu.splits, cpu.splits) << "frame " << frame;
  EXPECT_EQ(gpu.collapses, cpu.collapses) << "frame " << frame;
  EXPECT_EQ(gpu.probes_placed, cpu.probes_placed) << "frame " << frame;
  EXPECT_EQ(gpu.probes_freed, cpu.probes_freed) << "frame " << frame;
  EXPECT_EQ(gpu.failed_allocations, cpu.failed_allocations) << "frame " << frame;
  EXPECT_EQ(gpu.stale_entries, cpu.stale_entries) << "frame " << frame;
  EXPECT_EQ(gpu.deferred, cpu.deferred) << "frame " << frame;
  EXPECT_EQ(gpu.lost_entries, 0) << "frame " << frame;
}

// The live volume obeys every invariant, judged at the deepest max depth of the script (a lowered max
// depth leaves deeper leaves until they merge, which the validator would call too deep).
void expect_valid(formats::ProbeVolume live, int deepest, int frame) {
  live.info.max_depth = std::max(live.info.max_depth, deepest);
  const formats::ValidationReport report = formats::validate(live);
  ASSERT_TRUE(report.valid()) << "frame " << frame << ": " << report.violations.front().invariant << ": "
                              << report.violations.front().message;
}

} // namespace probebake::test
