// Skeleton placement (placement/methods/skeleton/skeleton.h): the medial axis of an analytic box room, surface
// coverage of the greedy selection on the Cornell box, thread-count invariance, and probes in every
// shared scene.
#include <gtest/gtest.h>

#include "bake_test_util.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/scene/ray_scene.h"
#include "probebake/placement/scene_sdf.h"
#include "probebake/formats/error.h"
#include "probebake/samples/scenes.h"
#include "skeleton.h"

namespace probebake::placement {
namespace {

// A closed room [0, size.x] x [0, size.y] x [0, size.z], every face looking inward (2 triangles each).
scene::Scene box_room(glm::vec3 size) {
  scene::Scene s;
  s.materials.push_back({});
  const glm::vec3 middle = 0.5f * size;
  const auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    const auto base = std::uint32_t(s.positions.size());
    s.positions.insert(s.positions.end(), {a, b, c, d});
    // Wound so that the front (CCW) faces the room's middle.
    const bool inward = glm::dot(glm::cross(b - a, c - a), middle - a) > 0.0f;
    s.triangles.push_back(inward ? glm::uvec3(base, base + 1, base + 2) : glm::uvec3(base, base + 2, base + 1));
    s.triangles.push_back(inward ? glm::uvec3(base, base + 2, base + 3) : glm::uvec3(base, base + 3, base + 2));
  };
  const float X = size.x, Y = size.y, Z = size.z;
  quad({0, 0, 0}, {X, 0, 0}, {X, 0, Z}, {0, 0, Z}); // floor
  quad({0, Y, 0}, {0, Y, Z}, {X, Y, Z}, {X, Y, 0}); // ceiling
  quad({0, 0, 0}, {0, 0, Z}, {0, Y, Z}, {0, Y, 0}); // x = 0
  quad({X, 0, 0}, {X, Y, 0}, {X, Y, Z}, {X, 0, Z}); // x = X
  quad({0, 0, 0}, {0, Y, 0}, {X, Y, 0}, {X, 0, 0}); // z = 0
  quad({0, 0, Z}, {X, 0, Z}, {X, Y, Z}, {0, Y, Z}); // z = Z
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    s.triangle_material.push_back(0);
    s.triangle_albedo.push_back(glm::vec3(0.5f));
    s.triangle_emission.push_back(glm::vec3(0.0f));
  }
  for (const glm::vec3& p : s.positions) s.bounds.extend(p);
  return s;
}

using test::load_generated; // bake_test_util.h: the generated scene through the real loader

float default_clearance(const scene::Scene& s) { return 0.02f * s.bounds.largest_extent(); }

TEST(Skeleton, BoxRoomSkeletonLiesOnItsMedialPlanes) {
  const glm::vec3 size(4.0f, 2.5f, 3.0f);
  const scene::Scene room = box_room(size);
  const float clearance = 0.08f;
  const scene::Bounds domain = default_domain(room, clearance);
  const SceneSdf sdf(room, skeleton_sdf_settings(domain));
  const DistanceGrid grid = sample_distance(sdf, room.bounds, 4.0f / 64.0f, 0);
  const std::vector<std::size_t> skeleton = skeleton_voxels(grid, clearance);
  ASSERT_FALSE(skeleton.empty());
  // A point of the medial axis has two nearest walls: the two smallest wall distances are equal. A ridge
  // voxel lies within one voxel of the sheet (measured: 1 voxel at worst, near the corners where three
  // sheets meet, where a diagonal axis crosses a sheet one voxel off).
  float worst = 0.0f;
  int on_central_sheet = 0;
  for (std::size_t i : skeleton) {
    const glm::vec3 p = grid.centre(grid.voxel_of(i));
    std::array<float, 6> d = {p.x, size.x - p.x, p.y, size.y - p.y, p.z, size.z - p.z};
    std::sort(d.begin(), d.end());
    worst = std::max(worst, d[1] - d[0]);
    // The sheet y = 1.25 between the floor and the ceiling spans x in [1.25, 2.75], z in [1.25, 1.75].
    if (std::abs(p.y - 1.25f) <= grid.voxel && p.x > 1.4f && p.x < 2.6f && p.z > 1.3f && p.z < 1.7f) ++on_central_sheet;
  }
  int free_voxels = 0;
  for (float d : grid.distance) free_voxels += d >= clearance ? 1 : 0;
  std::printf(
      "box room: %zu skeleton voxels of %d free (voxel %.4f m); worst |d2 - d1| = %.4f m; %d on the central sheet\n",
      skeleton.size(), free_voxels, double(grid.voxel), double(worst), on_central_sheet);
  EXPECT_LE(worst, 1.5f * grid.voxel);
  // The central sheet is 1.2 x 0.4 m: about (1.2 / v) * (0.4 / v) voxels, one or two thick.
  EXPECT_GE(on_central_sheet, int(0.8f * (1.2f / grid.voxel) * (0.4f / grid.voxel)));
  // A surface, not a volume: a small fraction of the free voxels.
  EXPECT_LT(skeleton.size(), std::size_t(free_voxels / 4));
}

struct Cornell {
  scene::Scene scene = load_generated(samples::cornell(), "skeleton_cornell");
  scene::RayScene rays{scene};
  float clearance = default_clearance(scene);
  SceneSdf sdf{scene, skeleton_sdf_settings(default_domain(scene, clearance))};
};

Cornell& cornell() {
  static Cornell c;
  return c;
}

// Open space: centres of a 24^3 grid over the scene bounds at least the clearance from every surface.
std::vector<glm::vec3> open_points(const Cornell& c) {
  std::vector<glm::vec3> out;
  const glm::vec3 lo = c.scene.bounds.min, step = (c.scene.bounds.max - lo) / 24.0f;
  for (int z = 0; z < 24; ++z)
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) {
        const glm::vec3 p = lo + (glm::vec3(x, y, z) + 0.5f) * step;
        if (c.sdf.distance(p) >= c.clearance) out.push_back(p);
      }
  return out;
}

TEST(Skeleton, GreedySelectionCoversTheCornellBoxSurface) {
  Cornell& c = cornell();
  SkeletonOptions o;
  o.clearance = c.clearance;
  const SkeletonResult r = skeleton_probes(c.rays, c.sdf, o);
  ASSERT_FALSE(r.probes.empty());
  // Measured independently of the placement's own samples: other samples, other reference points.
  const std::vector<SurfaceSample> samples = sample_surface(c.scene, 4096, 777);
  const std::vector<glm::vec3> open = open_points(c);
  const float seen = coverage(c.rays, r.probes, open, samples, 0);
  std::printf(
      "cornell, no budget: %zu probes, %d candidates from %d skeleton voxels; coverage %.4f (own samples %.4f); "
      "R %.1f -> %.1f in %d moves\n",
      r.probes.size(), r.report.candidates, r.report.skeleton_voxels, double(seen), double(r.report.coverage),
      r.report.objective_selected, r.report.objective_final, r.report.moves);
  EXPECT_GE(r.report.coverage, 0.999f);
  EXPECT_GE(seen, 0.99f);
  EXPECT_LE(r.probes.size(), 40u); // the paper's Cornell box needed 7
  EXPECT_GE(r.report.objective_final, r.report.objective_selected);
  for (const glm::vec3& p : r.probes) EXPECT_GE(c.sdf.distance(p), c.clearance);
}

TEST(Skeleton, BudgetGivesThatManyProbesAndOptimisationRaisesTheObjective) {
  Cornell& c = cornell();
  SkeletonOptions o;
  o.clearance = c.clearance;
  o.probes = 24;
  const SkeletonResult r = skeleton_probes(c.rays, c.sdf, o);
  EXPECT_EQ(r.probes.size(), 24u);
  std::printf("cornell, 24 probes: R %.2f -> %.2f in %d moves, coverage %.4f\n", r.report.objective_selected,
              r.report.objective_final, r.report.moves, double(r.report.coverage));
  EXPECT_GT(r.report.objective_final, r.report.objective_selected);
  EXPECT_GT(r.report.moves, 0);
}

TEST(Skeleton, SameProbesWhateverTheThreadCount) {
  Cornell& c = cornell();
  SkeletonOptions o;
  o.clearance = c.clearance;
  o.probes = 16;
  o.threads = 1;
  const SkeletonResult one = skeleton_probes(c.rays, c.sdf, o);
  o.threads = 2;
  const SkeletonResult two = skeleton_probes(c.rays, c.sdf, o);
  ASSERT_EQ(one.probes.size(), two.probes.size());
  EXPECT_EQ(std::memcmp(one.probes.data(), two.probes.data(), one.probes.size() * sizeof(glm::vec3)), 0);
  EXPECT_EQ(one.report.objective_final, two.report.objective_final);
}

TEST(Skeleton, EveryGeneratedAndSharedSceneGetsProbes) {
  std::vector<std::pair<std::string, scene::Scene>> scenes;
  scenes.emplace_back("leak", load_generated(samples::leak(), "skeleton_leak"));
  scenes.emplace_back("triangle", load_generated(samples::triangle(), "skeleton_triangle"));
  const std::filesystem::path shared = PROBEBAKE_SHARED_SCENES;
  if (std::filesystem::exists(shared))
    for (const auto& entry : std::filesystem::recursive_directory_iterator(shared)) {
      const auto ext = entry.path().extension();
      if (ext == ".glb" || ext == ".gltf")
        scenes.emplace_back(entry.path().filename().string(), scene::load_scene(entry.path()));
    }
  std::sort(scenes.begin(), scenes.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [name, s] : scenes) {
    const auto start = std::chrono::steady_clock::now();
    const scene::RayScene rays(s);
    SkeletonOptions o;
    o.clearance = default_clearance(s);
    const SceneSdf sdf(s, skeleton_sdf_settings(default_domain(s, o.clearance)));
    const SkeletonResult r = skeleton_probes(rays, sdf, o);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s: %zu probes, coverage %.4f, %.2f s (SDF, skeleton, selection)\n", name.c_str(), r.probes.size(),
                double(r.report.coverage), seconds);
    EXPECT_GE(r.probes.size(), 1u) << name;
    for (const glm::vec3& p : r.probes) EXPECT_GE(sdf.distance(p), o.clearance) << name;
  }
}

TEST(Skeleton, RefusesBadOptions) {
  Cornell& c = cornell();
  SkeletonOptions o;
  o.clearance = 0.0f;
  EXPECT_THROW(skeleton_probes(c.rays, c.sdf, o), Error);
  o.clearance = c.clearance;
  o.probes = -1;
  EXPECT_THROW(skeleton_probes(c.rays, c.sdf, o), Error);
  o.probes = 0;
  o.voxel_size = 1e-6f;
  EXPECT_THROW(skeleton_probes(c.rays, c.sdf, o), Error);
}

} // namespace
} // namespace probebake::placement
