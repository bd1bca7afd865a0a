// Bakes of the real scenes in ../shared/scenes (when present): valid files, probes outside geometry.
#include <cstdio>
#include <functional>

#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/formats/error.h"
#include "probebake/formats/validate.h"

namespace probebake::test {
namespace {

const std::filesystem::path kScenes = PROBEBAKE_SHARED_SCENES;

// Calls `visit` with every .glb/.gltf of ../shared/scenes, loaded, inside a trace naming the file.
void for_each_shared_scene(const std::function<void(const std::filesystem::path&, const scene::Scene&)>& visit) {
  for (const auto& dir : std::filesystem::directory_iterator(kScenes)) {
    if (!dir.is_directory()) continue;
    for (const auto& f : std::filesystem::directory_iterator(dir.path())) {
      if (f.path().extension() != ".glb" && f.path().extension() != ".gltf") continue;
      SCOPED_TRACE(f.path().string());
      visit(f.path(), scene::load_scene(f.path(), {.require_triangles = true}));
    }
  }
}

TEST(SharedBake, EverySharedSceneBakesValidWithProbesOutsideGeometry) {
  if (!std::filesystem::exists(kScenes)) GTEST_SKIP() << "no ../shared/scenes here";
  int baked = 0;
  for_each_shared_scene([&](const std::filesystem::path&, const scene::Scene& s) {
    bake::BakeResult r;
    try {
      r = bake::bake(s, test_settings());
    } catch (const Error& e) { // no shipped scene may bake to zero probes (issue #13)
      ADD_FAILURE() << e.what();
      return;
    }
    const auto report = formats::validate(r.volume);
    EXPECT_TRUE(report.valid()) << (report.violations.empty() ? "" : report.violations[0].message);
    const scene::RayScene rays(s);
    for (const gpu::Probe& p : r.volume.probes)
      if (p.link != 0) {
        EXPECT_FALSE(inside_geometry(rays, p.position));
      }
    ++baked;
  });
  EXPECT_GE(baked, 7); // every scene of ../shared/scenes, box_draco included (a larger root cube: ARCHITECTURE.md)
}

// glTF doubleSided (#19): each shared scene wound the other way with every material double-sided is the
// same scene by the spec. A scene whose materials are all double-sided already must place exactly the
// same probes (winding no longer means anything in it); the others are reported (placement only).
TEST(SharedBake, ReversedDoubleSidedSharedScenesBakeValid) {
  if (!std::filesystem::exists(kScenes)) GTEST_SKIP() << "no ../shared/scenes here";
  bake::BakeSettings settings = test_settings();
  settings.lighting.enabled = false;
  settings.runtime_lighting = false;
  int compared = 0;
  for_each_shared_scene([&](const std::filesystem::path& path, const scene::Scene& s) {
    const scene::Scene flipped = reversed_double_sided(s);
    bool all_double_sided = true;
    for (std::size_t t = 0; t < s.triangles.size(); ++t)
      all_double_sided = all_double_sided && scene::is_double_sided(s, t);
    int counts[2] = {-1, -1}; // -1: the bake refused (no probes placed)
    std::vector<glm::vec3> positions[2];
    for (int k = 0; k < 2; ++k) {
      try {
        const bake::BakeResult r = bake::bake(k == 0 ? s : flipped, settings);
        counts[k] = r.report.probes;
        for (const gpu::Probe& p : r.volume.probes)
          if (p.link != 0) positions[k].push_back(p.position);
        if (k == 1) {
          const auto report = formats::validate(r.volume);
          EXPECT_TRUE(report.valid()) << (report.violations.empty() ? "" : report.violations[0].message);
          const scene::RayScene rays(flipped);
          for (const glm::vec3& p : positions[1]) EXPECT_FALSE(inside_geometry(rays, p));
        }
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no probes placed"), std::string::npos) << e.what();
      }
    }
    std::printf("%s: probes original %d, reversed double-sided %d%s\n", path.filename().string().c_str(), counts[0],
                counts[1], all_double_sided ? " (all materials double-sided)" : "");
    if (all_double_sided) {
      EXPECT_GT(counts[0], 0) << "a refused bake on both sides would compare nothing";
      EXPECT_EQ(counts[1], counts[0]);
      EXPECT_EQ(positions[1], positions[0]);
      ++compared;
    }
  });
  std::printf("%d scenes all double-sided\n", compared);
  EXPECT_GE(compared, 2); // CornellBox.glb and its Draco twin: without them the equality above is never tested
}

} // namespace
} // namespace probebake::test
