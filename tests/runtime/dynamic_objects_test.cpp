// Dynamic objects in the runtime (format 1.3; docs/RUNTIME.md "Moving objects"): a cube appended by hand to
// the baked shallow Cornell box (its own BVH, object space, after the static nodes and triangles) moves
// through the room by FrameInputs::object_poses. The GPU memory update must reshape the tree exactly as the
// CPU reference does with the posed cube (memory_reference.h), the GPU's rays must hit the posed cube where a
// brute-force CPU trace does, and bad poses must be refused without changing anything.
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "memory_reference.h"
#include "probebake/dynamic/animation.h"
#include "probebake/formats/trace_mesh.h"
#include "probebake/formats/validate.h"
#include "probebake/samples/scenes.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using DynamicObjectsTest = RuntimeTest;

// Appends a single-sided cube [-half, half]^3 (object space, 12 triangles, outward normals) resting at
// `rest`: tree root (inner) -> {inner -> {x faces, y faces}, z faces}, 4 faces per leaf.
formats::ProbeVolume with_cube(const formats::ProbeVolume& base, glm::vec3 rest, float half) {
  formats::ProbeVolume v = base;
  const int first = int(v.trace_faces.size());
  std::vector<formats::TraceInputTriangle> triangles;
  for (int axis = 0; axis < 3; ++axis) {
    glm::vec3 a(0.0f), u(0.0f), w(0.0f);
    a[axis] = 1.0f, u[(axis + 1) % 3] = 1.0f, w[(axis + 2) % 3] = 1.0f; // u x w = a
    for (const float side : {-1.0f, 1.0f}) {
      const glm::vec3 c = side * half * a;
      glm::vec3 q[4] = {c - half * u - half * w, c + half * u - half * w, c + half * u + half * w,
                        c - half * u + half * w};
      if (side < 0.0f) std::swap(q[1], q[3]); // counter-clockwise seen from outside
      for (const auto& [i, j] : {std::pair{1, 2}, std::pair{2, 3}}) {
        formats::TraceInputTriangle t;
        t.corners[0] = q[0], t.corners[1] = q[i], t.corners[2] = q[j];
        t.albedo = glm::vec3(0.5f);
        triangles.push_back(t);
      }
    }
  }
  const auto node = [](int first_child_or_triangle, int count) {
    gpu::BvhNode n{};
    n.first = first_child_or_triangle;
    n.count = count;
    return n;
  };
  // root: children 1, 2; node 1: children 3, 4; leaves: z faces, x faces, y faces.
  const gpu::BvhNode nodes[] = {node(1, 0), node(3, 0), node(8, 4), node(0, 4), node(4, 4)};
  const int tree = formats::TraceMeshBuilder(v).add_tree(formats::TraceTreeInput{nodes, triangles});
  gpu::DynamicObject o{};
  o.lower = glm::vec3(-half);
  o.upper = glm::vec3(half);
  o.bvh_root = tree;
  o.bvh_node_count = v.trace_trees[std::size_t(tree)].node_count;
  o.first_triangle = first;
  o.triangle_count = 12;
  o.rest_rows[0] = glm::vec4(1.0f, 0.0f, 0.0f, rest.x);
  o.rest_rows[1] = glm::vec4(0.0f, 1.0f, 0.0f, rest.y);
  o.rest_rows[2] = glm::vec4(0.0f, 0.0f, 1.0f, rest.z);
  v.dynamic_objects.push_back(o);
  formats::sync_info_counts(v);
  return v;
}

glm::vec3 in_root(const formats::ProbeVolume& v, glm::vec3 fraction) {
  return v.info.root_min + fraction * v.info.root_size;
}

runtime::ObjectPose at(glm::vec3 position) { return {0, glm::translate(glm::mat4(1.0f), position)}; }

bool finite_probes(const formats::ProbeVolume& v) {
  for (const gpu::Probe& p : v.probes) {
    if (p.link == 0) continue;
    bool finite = std::isfinite(p.hit_fraction) && std::isfinite(p.backface_fraction);
    for (float c : p.irradiance_sh) finite = finite && std::isfinite(c);
    if (!finite) return false;
  }
  return true;
}

TEST_F(DynamicObjectsTest, HandBuiltCubeIsAValidVolume) {
  const formats::ProbeVolume v = with_cube(shallow_cornell(), in_root(shallow_cornell(), glm::vec3(1.5f)), 0.05f);
  const formats::ValidationReport report = formats::validate(v);
  ASSERT_TRUE(report.valid()) << report.violations.front().invariant << ": " << report.violations.front().message;
  auto gpu = runtime::Volume::upload(context(), v);
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  ASSERT_EQ(gpu.value().dynamic_objects().size(), 1u);
  EXPECT_EQ(gpu.value().object_pose(0), dynamic::rest_pose(v.dynamic_objects[0]));
  auto back = gpu.value().read_back();
  ASSERT_TRUE(back.ok());
  ASSERT_EQ(back.value().dynamic_objects.size(), 1u);
  EXPECT_EQ(back.value().dynamic_objects[0].bvh_root, v.dynamic_objects[0].bvh_root);
  EXPECT_TRUE(gpu.value().validate_live().ok());
}

// The cube comes in from outside the root cube, rests in open space, moves, and goes back out: the GPU and
// the CPU give the same tree every frame; back out, the tree and the pools are those before it came.
TEST_F(DynamicObjectsTest, GpuAndCpuReshapeTheSameTreeAroundAMovingCube) {
  const formats::ProbeVolume& base = shallow_cornell();
  // Big enough to hold the centres of the depth-2 cells around the room's centre: inside a solid they are
  // blind and refine towards the cube they see.
  const float half = 0.13f * base.info.root_size;
  const glm::vec3 rest = in_root(base, glm::vec3(1.4f, 0.5f, 0.5f));
  auto gpu = runtime::Volume::upload(context(), with_cube(base, rest, half), dynamic_options());
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  auto start = gpu.value().read_back();
  ASSERT_TRUE(start.ok()) << start.status().message;
  Cpu cpu(start.value());

  struct Scripted {
    Step step;
    std::vector<runtime::ObjectPose> poses;
  };
  std::vector<Scripted> script(20);
  script[0].step = {{root_box(base)}, 3}; // refine to depth 3 and settle
  script[8].poses = {at(in_root(base, glm::vec3(0.5f)))};
  script[11].poses = {at(in_root(base, glm::vec3(0.53f, 0.5f, 0.47f)))};
  script[14].poses = {at(rest)};
  constexpr int kSettled = 8;

  Canonical settled;
  int splits = 0, merges = 0, placed = 0, freed = 0, moved = 0;
  for (int frame = 1; frame <= int(script.size()); ++frame) {
    const Scripted& s = script[std::size_t(frame - 1)];
    runtime::FrameInputs in;
    in.changed_boxes = s.step.boxes;
    in.max_depth = s.step.max_depth;
    in.object_poses = s.poses;
    auto stats = gpu.value().run_frame(in);
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    moved += stats.value().light.moved_objects;
    const dynamic::TreeFrameStats cpu_stats = cpu.frame(s.step, s.poses);
    expect_same_stats(stats.value().memory, cpu_stats, frame);
    if (frame > kSettled) { // the cube's doing
      splits += stats.value().memory.splits;
      merges += stats.value().memory.collapses;
      placed += stats.value().memory.probes_placed;
      freed += stats.value().memory.probes_freed;
    }
    auto live = gpu.value().read_back();
    ASSERT_TRUE(live.ok()) << live.status().message;
    const Canonical g = canonical(live.value());
    ASSERT_EQ(first_difference(g, canonical(cpu.volume)), "") << "frame " << frame;
    ASSERT_TRUE(finite_probes(live.value())) << "frame " << frame;
    if (frame % 4 == 0) expect_valid(live.value(), 3, frame);
    if (frame == kSettled) settled = g;
    EXPECT_EQ(stats.value().memory.free_probes, cpu.tree.free_probes()) << "frame " << frame;
  }
  const Canonical end = canonical(cpu.volume);
  std::printf("[dynamic] %zu frames, %d moves: probes %d settled at depth 3; while and after the cube moved %d splits, "
              "%d merges, %d probes placed, %d freed; %d probes at the end; pools %d/%d/%d (start %d/%d/%d)\n",
              script.size(), moved, settled.probes, splits, merges, placed, freed, end.probes, end.probes, end.batches,
              end.clusters, settled.probes, settled.batches, settled.clusters);
  EXPECT_EQ(moved, 3);
  EXPECT_GT(splits, 0);
  EXPECT_GT(merges, 0);
  EXPECT_GT(placed, 0);
  EXPECT_EQ(gpu.value().object_pose(0), at(rest).world_from_object);
  EXPECT_EQ(end.leaves, settled.leaves);
  EXPECT_EQ(end.probes, settled.probes);
  EXPECT_EQ(end.batches, settled.batches);
  EXPECT_EQ(end.clusters, settled.clusters);
  EXPECT_TRUE(gpu.value().validate_live().ok());
}

// Ray counts of light_trace (every probe re-traced after the pose changed, no memory update) against a
// brute-force CPU trace of the rotated cube's world-space triangles.
TEST_F(DynamicObjectsTest, LightTraceSeesTheRotatedCubeAsTheCpuDoes) {
  const formats::ProbeVolume& base = shallow_cornell();
  const float half = 0.15f * base.info.root_size;
  const formats::ProbeVolume v = with_cube(base, in_root(base, glm::vec3(2.0f)), half);
  auto gpu = runtime::Volume::upload(context(), v);
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  ASSERT_TRUE(gpu.value().run_frame({}).ok());
  // Around the first probe (inside the cube) and in view of the others.
  glm::vec3 around(0.0f);
  for (const gpu::Probe& p : v.probes)
    if (p.link != 0) {
      around = p.position;
      break;
    }
  const glm::mat4 pose = glm::translate(glm::mat4(1.0f), around + 0.02f * base.info.root_size) *
                         glm::rotate(glm::mat4(1.0f), 0.6f, glm::normalize(glm::vec3(1.0f, 1.0f, 0.3f))) *
                         glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 0.7f, 1.2f));
  runtime::FrameInputs in;
  in.object_poses = {{0, pose}};
  auto stats = gpu.value().run_frame(in);
  ASSERT_TRUE(stats.ok()) << stats.status().message;
  const runtime::LightStats& l = stats.value().light;

  const std::vector<glm::mat4> posed{pose}, away{dynamic::rest_pose(v.dynamic_objects[0])};
  int front = 0, back = 0, miss = 0, cube_hits = 0, changed_by_cube = 0, traced = 0;
  for (const gpu::Probe& p : v.probes) {
    if (p.link == 0) continue;
    ++traced;
    for (int r = 0; r < v.lighting->rays; ++r) {
      const glm::vec3 dir(v.ray_directions[std::size_t(r)]);
      const NearestHit hit = nearest_hit(v, posed, p.position, dir);
      const NearestHit without = nearest_hit(v, away, p.position, dir);
      if (hit.triangle < 0) {
        ++miss;
        continue;
      }
      cube_hits += hit.triangle >= v.dynamic_objects[0].first_triangle ? 1 : 0;
      changed_by_cube += hit.triangle != without.triangle ? 1 : 0;
      const bool inside = glm::dot(hit.normal, dir) > 0.0f &&
                          (v.trace_faces[std::size_t(hit.triangle)].material & gpu::TRACE_FACE_DOUBLE_SIDED) == 0u;
      (inside ? back : front) += 1;
    }
  }
  std::printf("[dynamic] light_trace with the rotated cube: %d probes, front/back/miss GPU %d/%d/%d, CPU %d/%d/%d; %d "
              "rays hit the cube\n",
              l.traced_probes, l.front_hits, l.backface_hits, l.misses, front, back, miss, cube_hits);
  EXPECT_EQ(l.traced_probes, traced);
  EXPECT_GT(cube_hits, 10);
  EXPECT_GT(back, 10); // the probe inside sees the cube's back faces (where the walls it pierces are not nearer)
  EXPECT_GT(changed_by_cube, 10);
  EXPECT_EQ(l.front_hits, front);
  EXPECT_EQ(l.backface_hits, back);
  EXPECT_EQ(l.misses, miss);

  // The lattice measure of each probe's node (light_trace's hit and back-face fractions) with the cube.
  auto live = gpu.value().read_back();
  ASSERT_TRUE(live.ok());
  int compared = 0, differing = 0;
  formats::for_each_leaf(live.value(), [&](const formats::NodeCube& leaf) {
    const int value = live.value().octree[std::size_t(leaf.node)];
    if (value >= 0) return;
    const gpu::Probe& p = live.value().probes[std::size_t(~value)];
    const dynamic::LeafTrace t = measure(live.value(), leaf, posed);
    ++compared;
    differing += (p.hit_fraction != t.hit_fraction || p.backface_fraction != t.backface_fraction) ? 1 : 0;
  });
  EXPECT_GT(compared, 0);
  EXPECT_EQ(differing, 0) << "of " << compared << " probes";
  EXPECT_TRUE(finite_probes(live.value()));
  EXPECT_TRUE(gpu.value().validate_live().ok());
}

// Without the memory update, a moved object re-traces only the probes whose rays cross the box it swept
// (light_mark_moved) and relights only the records whose shadow rays may cross it (light_relight's shadow
// pairs): four closed rooms, one room's sphere moves, and the other rooms' probes keep their records. A twin
// whose sphere is already there at its first frame (everything traced with it) lands on the same probes.
TEST_F(DynamicObjectsTest, MovedObjectRetracesOnlyTheProbesWhoseRaysCrossItsBox) {
  samples::RoomsOptions rooms;
  rooms.count = 4;
  rooms.detail = 1;
  const formats::ProbeVolume v = bake_scene(samples::rooms(rooms), "rooms4");
  ASSERT_FALSE(v.dynamic_objects.empty());
  const glm::mat4 moved = glm::translate(dynamic::rest_pose(v.dynamic_objects[0]), glm::vec3(0.4f, 0.0f, 0.3f));
  auto gpu = runtime::Volume::upload(context(), v, {.hysteresis = 0.0f});
  auto twin = runtime::Volume::upload(context(), v, {.hysteresis = 0.0f});
  ASSERT_TRUE(gpu.ok() && twin.ok());
  runtime::FrameInputs move;
  move.object_poses = {{0, moved}};
  auto loaded = gpu.value().run_frame({});
  ASSERT_TRUE(loaded.ok()) << loaded.status().message;
  const int front_records = loaded.value().light.front_hits;
  auto first = twin.value().run_frame(move); // traced with the sphere moved from the start
  ASSERT_TRUE(first.ok()) << first.status().message;
  auto stats = gpu.value().run_frame(move);
  ASSERT_TRUE(stats.ok()) << stats.status().message;
  const int live = stats.value().live_probes, traced = stats.value().light.traced_probes;
  const int relit = stats.value().light.relit_records;
  for (int f = 0; f < 80; ++f) {
    ASSERT_TRUE(gpu.value().run_frame({}).ok());
    ASSERT_TRUE(twin.value().run_frame({}).ok());
  }
  auto a = gpu.value().read_back(), b = twin.value().read_back();
  ASSERT_TRUE(a.ok() && b.ok());
  float worst = 0.0f, brightest = 0.0f;
  for (std::size_t i = 0; i < b.value().probes.size(); ++i) {
    if (b.value().probes[i].link == 0) continue;
    for (int c = 0; c < gpu::PROBE_SH_FLOATS; ++c)
      worst = std::max(worst, std::abs(a.value().probes[i].irradiance_sh[c] - b.value().probes[i].irradiance_sh[c]));
    brightest = std::max(brightest, std::abs(b.value().probes[i].irradiance_sh[0]));
  }
  std::printf(
      "[dynamic] a room's sphere moved: %d of %d probes re-traced, %d of %d front records relit; after 80 frames "
      "%.2e of the brightest DC from a volume traced with it moved\n",
      traced, live, relit, front_records, double(worst / brightest));
  EXPECT_GT(traced, 0);
  EXPECT_GT(relit, 0);
  EXPECT_LT(relit, front_records / 2) << "the other rooms' lights cast no shadow of the sphere";
  EXPECT_LT(traced, live * 3 / 4) << "the other rooms' probes keep their records";
  EXPECT_LT(worst, 1e-4f * brightest);
  for (std::size_t i = 0; i < b.value().probes.size(); ++i)
    if (b.value().probes[i].link != 0) {
      ASSERT_EQ(a.value().probes[i].hit_fraction, b.value().probes[i].hit_fraction) << "probe " << i;
      ASSERT_EQ(a.value().probes[i].backface_fraction, b.value().probes[i].backface_fraction) << "probe " << i;
    }
}

// The all-probe sampler's visibility rays go through the cube: from points inside the closed cube every probe
// is hidden (a miss); once the cube has moved away, the points see what they see without the cube.
TEST_F(DynamicObjectsTest, AllProbeSamplerIsOccludedByTheCubeWhereItIs) {
  const formats::ProbeVolume& base = shallow_cornell();
  const float half = 0.1f * base.info.root_size;
  const glm::vec3 centre = in_root(base, glm::vec3(0.5f, 0.55f, 0.5f));
  auto gpu = runtime::Volume::upload(context(), with_cube(base, centre, half));
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  std::vector<glm::vec3> positions, normals;
  for (int i = 0; i < 64; ++i) {
    const glm::vec3 u(float(i % 4), float((i / 4) % 4), float(i / 16));
    positions.push_back(centre + (u / 3.0f - 0.5f) * half); // a 4^3 lattice over the middle half of the cube
    normals.push_back(glm::normalize(glm::vec3(float(i % 3) - 1.0f, 1.0f, float(i % 5) - 2.0f)));
  }
  runtime::SampleStats inside, moved;
  ASSERT_TRUE(gpu.value().sample_irradiance(positions, normals, &inside, runtime::SampleMethod::all_probes).ok());
  runtime::FrameInputs in;
  in.object_poses = {at(in_root(base, glm::vec3(2.0f)))};
  ASSERT_TRUE(gpu.value().run_frame(in).ok());
  auto without = runtime::Volume::upload(context(), base);
  ASSERT_TRUE(without.ok()) << without.status().message;
  ASSERT_TRUE(without.value().run_frame({}).ok()); // the same light update as the moved cube's frame
  runtime::SampleStats alone;
  auto reference = without.value().sample_irradiance(positions, normals, &alone, runtime::SampleMethod::all_probes);
  ASSERT_TRUE(reference.ok());
  auto after = gpu.value().sample_irradiance(positions, normals, &moved, runtime::SampleMethod::all_probes);
  ASSERT_TRUE(after.ok());
  std::printf(
      "[dynamic] all-probe sampler: %zu of %zu points inside the cube miss, %zu after it moved away, %zu without it\n",
      inside.misses, positions.size(), moved.misses, alone.misses);
  EXPECT_EQ(inside.misses, positions.size());
  EXPECT_LT(alone.misses, positions.size() / 2);
  EXPECT_EQ(moved.misses, alone.misses);
  EXPECT_EQ(after.value(), reference.value()); // bit for bit: the cube out of the way changes nothing
}

// Static volumes pay nothing: the cube's volume has exactly two more buffers (the section and the instances);
// moving it allocates nothing, and a pose equal to the current one uploads nothing.
TEST_F(DynamicObjectsTest, PosesAllocateNothingAndStaticVolumesGetNoObjectBuffers) {
  const formats::ProbeVolume& base = shallow_cornell();
  const auto buffers_of = [&](const formats::ProbeVolume& v) {
    const std::size_t before = context().memory_stats().live_buffers;
    auto gpu = runtime::Volume::upload(context(), v, dynamic_options());
    EXPECT_TRUE(gpu.ok()) << gpu.status().message;
    return context().memory_stats().live_buffers - before;
  };
  const formats::ProbeVolume with = with_cube(base, in_root(base, glm::vec3(0.3f)), 0.05f * base.info.root_size);
  const std::size_t static_buffers = buffers_of(base), object_buffers = buffers_of(with);
  EXPECT_EQ(object_buffers, static_buffers + 2);

  auto gpu = runtime::Volume::upload(context(), with, dynamic_options());
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  ASSERT_TRUE(gpu.value().run_frame({}).ok());
  const runtime::MemoryStats before = context().memory_stats();
  for (int f = 0; f < 12; ++f) {
    runtime::FrameInputs in;
    in.object_poses = {
        at(in_root(base, glm::vec3(0.3f + 0.03f * float(f / 2), 0.4f, 0.5f)))}; // every other frame the same
    auto stats = gpu.value().run_frame(in);
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    EXPECT_EQ(stats.value().light.moved_objects, f % 2 == 0 ? 1 : 0) << "frame " << f;
  }
  const runtime::MemoryStats after = context().memory_stats();
  EXPECT_EQ(after.allocations, before.allocations);
  EXPECT_EQ(after.live_buffers, before.live_buffers);
  EXPECT_TRUE(gpu.value().validate_live().ok());
}

TEST_F(DynamicObjectsTest, BadPosesAreRefusedAndChangeNothing) {
  const formats::ProbeVolume v = with_cube(shallow_cornell(), in_root(shallow_cornell(), glm::vec3(0.5f)), 0.05f);
  auto gpu = runtime::Volume::upload(context(), v);
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  const glm::mat4 rest = gpu.value().object_pose(0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  glm::mat4 with_nan(1.0f), projective(1.0f), flat(1.0f);
  with_nan[3][1] = nan;
  projective[0][3] = 0.5f;                // last row 0.5 0 0 1
  flat[1][1] = 1e-5f, flat[2][2] = 1e-8f; // det 1e-13
  const std::vector<std::pair<std::vector<runtime::ObjectPose>, std::string>> bad{
      {{{0, with_nan}}, "not finite"},
      {{{0, projective}}, "not affine"},
      {{{0, flat}}, "singular"},
      {{{1, glm::mat4(1.0f)}}, "no such dynamic object"},
      {{{-1, glm::mat4(1.0f)}}, "no such dynamic object"},
      {{{0, glm::mat4(1.0f)}, {0, glm::mat4(1.0f)}}, "listed twice"}};
  for (const auto& [poses, reason] : bad) {
    runtime::FrameInputs in;
    in.object_poses = poses;
    auto refused = gpu.value().run_frame(in);
    ASSERT_FALSE(refused.ok()) << reason;
    EXPECT_EQ(refused.status().code, runtime::StatusCode::invalid_argument) << reason;
    EXPECT_NE(refused.status().message.find(reason), std::string::npos) << refused.status().message;
    EXPECT_NE(refused.status().message.find("object"), std::string::npos) << refused.status().message;
    EXPECT_EQ(gpu.value().object_pose(0), rest) << reason;
  }
  auto fine = gpu.value().run_frame({});
  ASSERT_TRUE(fine.ok()) << fine.status().message;
  EXPECT_EQ(fine.value().light.moved_objects, 0);
  EXPECT_TRUE(gpu.value().validate_live().ok());
}

} // namespace
} // namespace probebake::test
