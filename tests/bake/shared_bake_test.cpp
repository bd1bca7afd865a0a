// Bakes of the real scenes in ../shared/scenes (when present): valid files, probes outside geometry.
#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/formats/error.h"
#include "probebake/formats/validate.h"

namespace probebake::test {
namespace {

const std::filesystem::path kScenes = PROBEBAKE_SHARED_SCENES;

TEST(SharedBake, EverySharedSceneBakesValidWithProbesOutsideGeometry) {
  if (!std::filesystem::exists(kScenes)) GTEST_SKIP() << "no ../shared/scenes here";
  int baked = 0;
  for (const auto& dir : std::filesystem::directory_iterator(kScenes)) {
    if (!dir.is_directory()) continue;
    for (const auto& f : std::filesystem::directory_iterator(dir.path())) {
      if (f.path().extension() != ".glb" && f.path().extension() != ".gltf") continue;
      SCOPED_TRACE(f.path().string());
      const scene::Scene s = scene::load_scene(f.path(), {.require_triangles = true});
      bake::BakeResult r;
      try {
        r = bake::bake(s, test_settings());
      } catch (const Error& e) { // the octree frees every probe of some open scenes (issue #13): said, not silent
        EXPECT_NE(std::string(e.what()).find("no probes placed"), std::string::npos) << e.what();
        continue;
      }
      const auto report = formats::validate(r.volume);
      EXPECT_TRUE(report.valid()) << (report.violations.empty() ? "" : report.violations[0].message);
      const scene::RayScene rays(s);
      for (const gpu::Probe& p : r.volume.probes)
        if (p.link != 0) {
          EXPECT_FALSE(inside_geometry(rays, p.position));
        }
      ++baked;
    }
  }
  EXPECT_GE(baked, 6); // box_draco: no octree probes until placement earns its adaptivity (issue #13)
}

} // namespace
} // namespace probebake::test
