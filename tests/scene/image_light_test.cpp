// EXT_lights_image_based read as the sky (gltf_image_light.cpp): the irradiance coefficients become radiance
// L_lm = E_lm / A_l, so that the sky gives back the coefficients' irradiance; rotation and intensity apply; a
// malformed light is an input error naming its place; the caller's --sky wins.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "mini_gltf.h"
#include "probebake/formats/error.h"
#include "probebake/scene/scene.h"

namespace probebake::test {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// A one-triangle file whose scene names image-based light 0 with these irradiance coefficients (9 RGB rows).
MiniGltf with_light(const nlohmann::json& coefficients, const nlohmann::json& extra = nlohmann::json::object()) {
  MiniGltf g = MiniGltf::triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  nlohmann::json light = extra;
  light["irradianceCoefficients"] = coefficients;
  light["specularImageSize"] = 16;
  light["specularImages"] = nlohmann::json::array();
  g.json["extensions"]["EXT_lights_image_based"]["lights"] = nlohmann::json::array({light});
  g.json["scenes"][0]["extensions"]["EXT_lights_image_based"]["light"] = 0;
  g.json["extensionsUsed"] = {"EXT_lights_image_based"};
  return g;
}

nlohmann::json rows(std::initializer_list<std::pair<int, glm::vec3>> set) {
  nlohmann::json c = nlohmann::json::array();
  for (int k = 0; k < 9; ++k) c.push_back({0.0, 0.0, 0.0});
  for (const auto& [k, v] : set) c[k] = {v.x, v.y, v.z};
  return c;
}

scene::Scene load(const MiniGltf& g, const std::string& name, const scene::LoadOptions& options = {}) {
  const auto path = test_dir(name) / "scene.glb";
  g.write_glb(path);
  return scene::load_scene(path, options);
}

// Irradiance on a surface facing `n` from the sky (midpoint rule over the sphere).
glm::vec3 irradiance(const sky::Sky& s, glm::vec3 n) {
  constexpr int kTheta = 256, kPhi = 512;
  glm::vec3 e(0.0f);
  for (int i = 0; i < kTheta; ++i)
    for (int j = 0; j < kPhi; ++j) {
      const float theta = kPi * (float(i) + 0.5f) / kTheta, phi = 2 * kPi * (float(j) + 0.5f) / kPhi;
      const glm::vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      const float cosine = glm::dot(d, n);
      if (cosine > 0.0f) e += s.radiance(d) * cosine * std::sin(theta) * (kPi / kTheta) * (2 * kPi / kPhi);
    }
  return e;
}

TEST(ImageBasedLight, ConstantIrradianceIsAConstantSkyTimesIntensity) {
  const glm::vec3 e00(2.0f, 1.0f, 0.5f);
  const scene::Scene s = load(with_light(rows({{0, e00}}), {{"intensity", 3.0}}), "ibl_constant");
  ASSERT_FALSE(s.sky.map.empty());
  EXPECT_EQ(s.sky.kind, gpu::SKY_KIND_ENVIRONMENT);
  const glm::vec3 expected = 3.0f * e00 * 0.282095f / kPi; // E(n) = E00 Y00 everywhere, L = E / pi
  for (const glm::vec3 d : {glm::vec3(0, 1, 0), glm::vec3(1, 0, 0), glm::vec3(0, -0.6f, 0.8f)})
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.sky.radiance(d)[c], expected[c], 1e-5f * expected[c]);
}

// E = E00 Y00 + E10 Y10 (a z gradient whose radiance stays positive: no clamp), rotated 90 degrees about +Y (+Z of
// the environment towards +X): the sky gives back that irradiance on the rotated normals, to the map's quadrature.
TEST(ImageBasedLight, TheSkyGivesBackTheCoefficientsIrradianceRotated) {
  const float s45 = std::sqrt(0.5f);
  const scene::Scene s =
      load(with_light(rows({{0, glm::vec3(4.0f)}, {2, glm::vec3(1.0f)}}), {{"rotation", {0.0, s45, 0.0, s45}}}),
           "ibl_rotated");
  const auto analytic = [](glm::vec3 n_environment) { return 4.0f * 0.282095f + 1.0f * 0.488603f * n_environment.z; };
  for (const auto& [world, environment] :
       {std::pair{glm::vec3(1, 0, 0), glm::vec3(0, 0, 1)}, std::pair{glm::vec3(-1, 0, 0), glm::vec3(0, 0, -1)},
        std::pair{glm::vec3(0, 1, 0), glm::vec3(0, 1, 0)}}) {
    const glm::vec3 e = irradiance(s.sky, world);
    std::printf("[ibl] normal %g %g %g: irradiance %.5f, coefficients %.5f\n", double(world.x), double(world.y),
                double(world.z), double(e.x), double(analytic(environment)));
    EXPECT_NEAR(e.x / analytic(environment), 1.0f, 1e-3f); // measured 3.2e-4 at most
  }
}

TEST(ImageBasedLight, MalformedLightsAreInputErrorsNamingThePlace) {
  const auto fails_with = [](const MiniGltf& g, const std::string& name, const std::string& says) {
    try {
      load(g, name);
      ADD_FAILURE() << name << " loaded";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  nlohmann::json eight = rows({});
  eight.erase(8);
  fails_with(with_light(eight), "ibl_eight", "lights[0].irradianceCoefficients: is not an array of 9");
  nlohmann::json huge = rows({});
  huge[4] = {1e300, 0.0, 0.0};
  fails_with(with_light(huge), "ibl_huge", "irradianceCoefficients[4]: is not finite");
  fails_with(with_light(rows({}), {{"rotation", {0.0, 0.0, 0.0, 2.0}}}), "ibl_rotation", "not a unit quaternion");
  fails_with(with_light(rows({}), {{"intensity", -1.0}}), "ibl_negative", "intensity: is negative");
  MiniGltf missing = with_light(rows({}));
  missing.json["scenes"][0]["extensions"]["EXT_lights_image_based"]["light"] = 3;
  fails_with(missing, "ibl_missing", "lights[3]: the scene's image-based light does not exist");
}

TEST(ImageBasedLight, TheCallersSkyWins) {
  const scene::Scene s =
      load(with_light(rows({{0, glm::vec3(1.0f)}})), "ibl_option", {.sky = sky::constant_sky(glm::vec3(0.25f))});
  EXPECT_TRUE(s.sky.map.empty());
  EXPECT_EQ(s.sky.colour, glm::vec3(0.25f));
}

} // namespace
} // namespace probebake::test
