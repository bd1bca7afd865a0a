// Shared helpers of the bake tests: generated scenes loaded through the real loader, and an independent
// inside-geometry check.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "probebake/bake/bake.h"
#include "probebake/formats/error.h"
#include "probebake/scene/ray_scene.h"
#include "probebake/samples/scene_builder.h"

namespace probebake::test {

// Writes the builder's .glb under the test temp dir and loads it like the CLI does.
scene::Scene load_generated(const samples::SceneBuilder& builder, const std::string& name);
std::filesystem::path write_generated(const samples::SceneBuilder& builder, const std::string& name);

// A loaded scene and its BVH (the RayScene keeps a pointer to the scene: both live on the heap).
struct Loaded {
  std::unique_ptr<scene::Scene> scene;
  std::unique_ptr<scene::RayScene> rays;
};
Loaded adopt(scene::Scene s);
// load_generated() with its BVH.
Loaded load(const samples::SceneBuilder& builder, const std::string& name);

// Independent of the bake's own dead-probe test: 1024 pseudo-random directions (not the bake's lattice);
// a point is inside geometry when more than half of the rays that hit anything hit a back face of a
// single-sided surface (RayHit::inside).
bool inside_geometry(const scene::RayScene& rays, glm::vec3 p);
// Distance to the nearest surface along those directions.
float nearest_surface(const scene::RayScene& rays, glm::vec3 p);

// The same scene by the glTF rule (#19): every triangle wound the other way and every material
// double-sided.
scene::Scene reversed_double_sided(scene::Scene s);

// `run` must throw probebake::Error (of `kind`, when given) whose message contains `part`; `success` is the
// failure reported when it returns instead.
template <typename Run>
void expect_refusal(Run&& run, const std::string& part, const char* success,
                    std::optional<ErrorKind> kind = std::nullopt) {
  try {
    run();
    ADD_FAILURE() << success;
  } catch (const Error& e) {
    if (kind) {
      EXPECT_EQ(e.kind(), *kind);
    }
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

// Small, fast settings for tests.
bake::BakeSettings test_settings();

} // namespace probebake::test
