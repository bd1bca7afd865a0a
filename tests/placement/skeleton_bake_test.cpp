// `--placement skeleton` through the whole bake: the budget, valid files, the same bytes for any thread
// count, and no shared scene without probes.
#include <gtest/gtest.h>

#include "bake_test_util.h"

#include <algorithm>
#include <filesystem>
#include <string>

#include "probebake/bake/bake.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "probebake/gpu_types.h"
#include "probebake/samples/scenes.h"
#include "probebake/scene/scene.h"

namespace probebake {
namespace {

using test::load_generated; // bake_test_util.h: the generated scene through the real loader

bake::BakeSettings skeleton_settings(int probes) {
  bake::BakeSettings s;
  s.placement = bake::Placement::skeleton;
  s.probe_budget = probes;
  s.surfels_per_probe = 64;
  s.svo_depth = 4;
  s.lighting.rays = 64;
  return s;
}

std::string first_violation(const formats::ValidationReport& r) {
  return r.violations.empty() ? std::string() : r.violations.front().invariant + ": " + r.violations.front().message;
}

TEST(SkeletonBake, BudgetOfProbesInAValidFile) {
  const scene::Scene s = load_generated(samples::cornell(), "cornell_skeleton");
  const bake::BakeResult r = bake::bake(s, skeleton_settings(40));
  std::printf("cornell --probes 40: %d probes (%d dead: %d moved, %d freed), %d SVO leaves\n", r.report.probes,
              r.report.dead_probes, r.report.moved_probes, r.report.freed_probes, r.report.svo_leaves);
  EXPECT_EQ(r.report.placed_probes, 40);
  EXPECT_GE(r.report.probes, 36); // at most a tenth freed by the lattice's dead-probe test
  EXPECT_EQ(r.volume.info.placement, gpu::PLACEMENT_SKELETON);
  for (const gpu::Probe& p : r.volume.probes)
    if (p.link != 0) {
      EXPECT_EQ(p.node, -1);
    }
  const formats::ValidationReport v = formats::validate(r.volume);
  EXPECT_TRUE(v.valid()) << first_violation(v);
  // The file round-trips and validates as bytes too.
  const std::vector<std::uint8_t> bytes = formats::write_probes(r.volume);
  EXPECT_TRUE(formats::validate_file(bytes, "cornell_skeleton.probes").valid());
}

TEST(SkeletonBake, SameBytesWithOneAndTwoThreads) {
  const scene::Scene s = load_generated(samples::cornell(), "cornell_skeleton_det");
  std::vector<std::vector<std::uint8_t>> files;
  for (const int threads : {1, 2}) {
    bake::BakeSettings settings = skeleton_settings(24);
    settings.threads = threads;
    files.push_back(formats::write_probes(bake::bake(s, settings).volume));
  }
  EXPECT_EQ(files[0], files[1]);
}

TEST(SkeletonBake, NoSharedSceneBakesToZeroProbes) {
  const std::filesystem::path shared = PROBEBAKE_SHARED_SCENES;
  if (!std::filesystem::exists(shared)) GTEST_SKIP() << "no " << shared;
  std::vector<std::filesystem::path> paths;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(shared)) {
    const auto ext = entry.path().extension();
    if (ext == ".glb" || ext == ".gltf") paths.push_back(entry.path());
  }
  std::sort(paths.begin(), paths.end());
  ASSERT_FALSE(paths.empty());
  for (const auto& path : paths) {
    bake::BakeSettings settings = skeleton_settings(0);
    settings.lighting.enabled = false;
    settings.runtime_lighting = false;
    const bake::BakeResult r = bake::bake(scene::load_scene(path), settings);
    std::printf("%s: %d probes\n", path.filename().c_str(), r.report.probes);
    EXPECT_GT(r.report.probes, 0) << path;
    const formats::ValidationReport v = formats::validate(r.volume);
    EXPECT_TRUE(v.valid()) << path << ": " << first_violation(v);
  }
}

} // namespace
} // namespace probebake
