// Error-driven octree refinement under a probe budget (placement/methods/octree/refine_octree.h): depth goes where the
// light varies over visible surface, the budget is honoured, bakes are deterministic, and no shipped
// scene bakes to zero probes.
#include <algorithm>
#include <cstdio>

#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/scene/ray_scene.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "probebake/samples/geometry.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

constexpr float kRoom = 8.0f;   // the room is [0, 8] x [0, 4] x [0, 8]
constexpr float kCorner = 2.0f; // the detailed region: x, z in [6, 8], y < 2

// A big empty room with one cluttered corner: twenty small coloured blocks and a point light among them
// in the +x +z corner; the other 98 % of the floor area is bare and lit from afar.
samples::SceneBuilder cluttered_corner_room() {
  samples::SceneBuilder b("cluttered_corner");
  const auto white = b.add_material({.name = "white", .albedo = glm::vec3(0.7f)});
  b.add_mesh_node(
      "room",
      b.add_mesh("room", samples::box({0, 0, 0}, {kRoom, kRoom / 2, kRoom}, samples::Facing::inward, 4), white));
  for (int i = 0; i < 20; ++i) {
    const float x = kRoom - kCorner + 0.15f + 0.4f * float(i % 4);
    const float z = kRoom - kCorner + 0.15f + 0.35f * float(i / 4);
    const float h = 0.1f + 0.05f * float((i * 7) % 5);
    const glm::vec3 colour(0.2f + 0.7f * float(i % 3 == 0), 0.2f + 0.7f * float(i % 3 == 1),
                           0.2f + 0.7f * float(i % 3 == 2));
    const auto m = b.add_material({.name = "block" + std::to_string(i), .albedo = colour});
    b.add_mesh_node("block" + std::to_string(i),
                    b.add_mesh("block" + std::to_string(i),
                               samples::box({x, 0, z}, {x + 0.2f, h, z + 0.2f}, samples::Facing::outward), m));
  }
  const auto light = b.add_light({.name = "lamp", .intensity = 20.0f});
  b.add_light_node("lamp", light, {kRoom - 1.0f, 0.6f, kRoom - 1.0f});
  return b;
}

bool in_corner(glm::vec3 p) { return p.x > kRoom - kCorner && p.z > kRoom - kCorner && p.y < kCorner; }

bake::BakeSettings error_settings(int budget) {
  bake::BakeSettings s = test_settings();
  s.split_rule = bake::SplitRule::error;
  s.probe_budget = budget;
  s.max_depth = 6;
  s.runtime_lighting = false;
  s.clearance = 0.04f; // the default (2 % of 8 m) is wider than the gaps between the blocks
  return s;
}

double mean_depth(const formats::ProbeVolume& v, bool corner) {
  double sum = 0.0;
  int n = 0;
  for (const gpu::Probe& p : v.probes)
    if (p.link != 0 && in_corner(p.position) == corner) {
      sum += p.depth;
      ++n;
    }
  return n > 0 ? sum / n : 0.0;
}

TEST(Refine, DepthGoesToTheDetailedCorner) {
  const scene::Scene s = load_generated(cluttered_corner_room(), "cluttered_corner");
  const bake::BakeResult r = bake::bake(s, error_settings(200));
  EXPECT_TRUE(formats::validate(r.volume).valid());
  std::vector<int> corner(7, 0), rest(7, 0);
  for (const gpu::Probe& p : r.volume.probes)
    if (p.link != 0) ++(in_corner(p.position) ? corner : rest)[std::size_t(p.depth)];
  for (int d = 0; d < 7; ++d)
    std::printf("depth %d: corner %d, rest %d\n", d, corner[std::size_t(d)], rest[std::size_t(d)]);
  // The corner is 1/64 of the room's volume and 1/16 of its floor; the refinement spends its depth there.
  const double corner_mean = mean_depth(r.volume, true), rest_mean = mean_depth(r.volume, false);
  std::printf("mean depth: corner %.2f, rest %.2f\n", corner_mean, rest_mean);
  EXPECT_GT(corner_mean, rest_mean + 1.0);
  const int deepest =
      int(std::find_if(corner.rbegin(), corner.rend(), [](int n) { return n > 0; }).base() - corner.begin()) - 1;
  EXPECT_GE(deepest, 4);
  EXPECT_EQ(rest[std::size_t(deepest)], 0) << "the deepest level lies in the corner only";
}

TEST(Refine, BudgetIsHonouredAndNearlySpent) {
  const scene::Scene s = load_generated(cluttered_corner_room(), "cluttered_corner");
  for (const bake::SplitRule rule : {bake::SplitRule::error, bake::SplitRule::surface})
    for (int budget : {1, 40, 150}) {
      SCOPED_TRACE(budget);
      bake::BakeSettings settings = error_settings(budget);
      settings.split_rule = rule;
      const bake::BakeResult r = bake::bake(s, settings);
      std::printf("%s, budget %d: placed %d, live %d (freed %d)\n",
                  rule == bake::SplitRule::error ? "error" : "surface", budget, r.report.placed_probes, r.report.probes,
                  r.report.freed_probes);
      EXPECT_LE(r.report.placed_probes, budget);
      EXPECT_LE(r.report.probes, budget);
      EXPECT_GE(r.report.placed_probes, budget == 1 ? 1 : int(0.9 * budget));
    }
}

TEST(Refine, SameBytesForAnyThreadCount) {
  const scene::Scene s = load_generated(cluttered_corner_room(), "cluttered_corner");
  for (const bake::SplitRule rule : {bake::SplitRule::error, bake::SplitRule::surface}) {
    bake::BakeSettings one = error_settings(120), two = one;
    one.split_rule = two.split_rule = rule;
    one.threads = 1;
    two.threads = 2;
    const auto a = formats::write_probes(bake::bake(s, one).volume);
    const auto b = formats::write_probes(bake::bake(s, two).volume);
    EXPECT_EQ(a, b);
  }
}

// box_draco is one closed box seen from outside: inside its bounds everything is solid, and the bake
// placed 0 probes (issue #13) until the root cube was tripled around such scenes (refine_root.h).
TEST(Refine, BoxDracoBakesProbesAroundTheBox) {
  const std::filesystem::path box = std::filesystem::path(PROBEBAKE_SHARED_SCENES) / "box_draco" / "Box_Draco.glb";
  if (!std::filesystem::exists(box)) GTEST_SKIP() << "no " << box;
  const scene::Scene s = scene::load_scene(box, {.require_triangles = true});
  const scene::RayScene rays(s);
  struct Case {
    const char* name;
    bake::BakeSettings settings;
  };
  bake::BakeSettings grid = test_settings(), skeleton = test_settings();
  grid.placement = bake::Placement::grid;
  grid.grid_resolution = 4;
  skeleton.placement = bake::Placement::skeleton;
  skeleton.probe_budget = 16;
  // Every method: no shipped scene may bake to zero probes (issue #13).
  for (Case c : {Case{"hit-fraction rule", test_settings()}, Case{"error rule", error_settings(64)}, Case{"grid", grid},
                 Case{"skeleton", skeleton}}) {
    SCOPED_TRACE(c.name);
    c.settings.clearance = 0.0f;
    const bake::BakeResult r = bake::bake(s, c.settings);
    std::printf("%s: %d probes\n", c.name, r.report.probes);
    EXPECT_TRUE(r.report.surrounded_root);
    EXPECT_GT(r.report.probes, 0);
    EXPECT_TRUE(formats::validate(r.volume).valid());
    for (const gpu::Probe& p : r.volume.probes)
      if (p.link != 0) {
        EXPECT_FALSE(inside_geometry(rays, p.position));
      }
  }
}

// A room has open space inside its bounds: its root cube stays the bounds' cube.
TEST(Refine, RoomsKeepTheirRootCube) {
  const scene::Scene s = load_generated(cluttered_corner_room(), "cluttered_corner");
  const bake::BakeResult r = bake::bake(s, error_settings(8));
  EXPECT_FALSE(r.report.surrounded_root);
  EXPECT_EQ(r.volume.info.root_size, bake::volume_info(s, error_settings(8)).root_size);
}

// A flat world of 64 rooms side by side (49 x 3 x 49 m): an eighth of its root cube is 6.2 m, so no point of
// the root's 8^3 grid lies in the 3 m of the rooms' height and the world was taken for one closed object
// (root tripled, probes around it). At 0.15 m the grid over its bounds finds the rooms; at the default
// clearance (2 % of 49 m, 0.99 m) no grid point is that far from every surface (the tables stand under the
// rooms' centres) and the points in front of the surfaces find them: before, that bake placed no probe.
TEST(Refine, AFlatWorldOfRoomsKeepsItsRootCube) {
  const scene::Scene s = load_generated(samples::rooms({.count = 64, .detail = 1, .seed = 1}), "flat_world");
  for (const float clearance : {0.15f, 0.0f}) {
    bake::BakeSettings settings = test_settings();
    settings.max_depth = 4;
    settings.clearance = clearance;
    settings.lighting.enabled = false;
    settings.runtime_lighting = false;
    const bake::BakeResult r = bake::bake(s, settings);
    EXPECT_FALSE(r.report.surrounded_root) << clearance;
    EXPECT_EQ(r.volume.info.root_size, bake::volume_info(s, settings).root_size);
    int in_rooms = 0;
    for (const gpu::Probe& p : r.volume.probes)
      in_rooms += p.link != 0 && p.position.y > 0.0f && p.position.y < 3.0f ? 1 : 0;
    std::printf("flat world at clearance %.3f m: %d probes, %d of them between floor and ceiling height\n",
                r.report.clearance, r.report.probes, in_rooms);
    EXPECT_GT(in_rooms, 64) << clearance; // more than one per room
  }
}

TEST(Refine, SettingsAreChecked) {
  bake::BakeSettings s = test_settings();
  s.split_rule = bake::SplitRule::error; // no budget
  EXPECT_THROW(bake::check_settings(s), Error);
  s.probe_budget = 10;
  s.uniform_share = 1.5f;
  EXPECT_THROW(bake::check_settings(s), Error);
  s.uniform_share = 0.5f;
  EXPECT_NO_THROW(bake::check_settings(s));
  s.split_rule = bake::SplitRule::surface;
  EXPECT_NO_THROW(bake::check_settings(s));
  s.split_rule = bake::SplitRule::hit_fraction; // a budget the rule would ignore
  EXPECT_THROW(bake::check_settings(s), Error);
}

} // namespace
} // namespace probebake::test
