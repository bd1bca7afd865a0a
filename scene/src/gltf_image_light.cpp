// EXT_lights_image_based (a vendor extension of Babylon.js and Adobe Dimension; docs/GLTF.md): the image-based
// light the loaded scene names, read as the sky. Only its irradiance is used: the 9 x RGB spherical-harmonic
// coefficients of irradiance up to l = 2 (Ramamoorthi and Hanrahan 2001), in the real SH basis in the order
// (0,0), (1,-1), (1,0), (1,1), (2,-2), (2,-1), (2,0), (2,1), (2,2) of glTF's axes, as Babylon.js reads them. The
// radiance with that irradiance is L_lm = E_lm / A_l (A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4), rotated by the
// light's quaternion and scaled by its intensity, written into a kEnvironmentWidth x kEnvironmentHeight map and
// clamped at zero (a band-limited radiance rings below zero). The prefiltered specular cube maps are not read.
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include <fmt/core.h>
#include <glm/gtc/quaternion.hpp>
#include <tiny_gltf.h>

#include "gltf_internal.h"
#include "probebake/gpu_types.h"

namespace probebake::scene::detail {
namespace {

constexpr const char* kExtension = "EXT_lights_image_based";

// The real SH basis up to l = 2 at unit direction d, in the order above.
std::array<float, 9> sh_basis(glm::vec3 d) {
  return {0.282095f,
          0.488603f * d.y,
          0.488603f * d.z,
          0.488603f * d.x,
          1.092548f * d.x * d.y,
          1.092548f * d.y * d.z,
          0.315392f * (3.0f * d.z * d.z - 1.0f),
          1.092548f * d.x * d.z,
          0.546274f * (d.x * d.x - d.y * d.y)};
}

float finite_number(const tinygltf::Value& v, const std::string& place, const Context& ctx) {
  if (!v.IsNumber()) ctx.fail(place, "is not a number");
  const double x = v.GetNumberAsDouble();
  if (!std::isfinite(x) || std::abs(x) > 1e30) ctx.fail(place, "is not finite (or beyond 1e30)");
  return float(x);
}

// The radiance SH (L_lm per channel) of the light's irradiance coefficients.
std::array<glm::vec3, 9> radiance_coefficients(const tinygltf::Value& light, const std::string& place,
                                               const Context& ctx) {
  const tinygltf::Value& rows = member(light, "irradianceCoefficients");
  const std::string where = place + ".irradianceCoefficients";
  if (!rows.IsArray() || rows.ArrayLen() != 9) ctx.fail(where, "is not an array of 9 RGB triples");
  constexpr float pi = std::numbers::pi_v<float>;
  constexpr std::array<float, 9> lambert{pi,     2 * pi / 3, 2 * pi / 3, 2 * pi / 3, pi / 4,
                                         pi / 4, pi / 4,     pi / 4,     pi / 4};
  std::array<glm::vec3, 9> radiance{};
  for (int k = 0; k < 9; ++k) {
    const tinygltf::Value& rgb = rows.Get(k);
    const std::string at = fmt::format("{}[{}]", where, k);
    if (!rgb.IsArray() || rgb.ArrayLen() != 3) ctx.fail(at, "is not an RGB triple");
    for (int c = 0; c < 3; ++c)
      radiance[std::size_t(k)][c] = finite_number(rgb.Get(c), at, ctx) / lambert[std::size_t(k)];
  }
  return radiance;
}

glm::quat rotation_of(const tinygltf::Value& light, const std::string& place, const Context& ctx) {
  const tinygltf::Value& q = member(light, "rotation");
  if (q.Type() == tinygltf::NULL_TYPE) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  if (!q.IsArray() || q.ArrayLen() != 4) ctx.fail(place + ".rotation", "is not a quaternion [x, y, z, w]");
  float xyzw[4];
  for (int i = 0; i < 4; ++i) xyzw[i] = finite_number(q.Get(i), place + ".rotation", ctx);
  const glm::quat rotation(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
  const float length = glm::length(rotation);
  if (!(std::abs(length - 1.0f) < 1e-3f)) ctx.fail(place + ".rotation", "is not a unit quaternion");
  return rotation / length;
}

// The index of the light the loaded scene names, or nothing.
std::optional<int> named_light(const tinygltf::Model& model) {
  if (model.scenes.empty()) return std::nullopt;
  const int s = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (std::size_t(s) >= model.scenes.size()) return std::nullopt; // root_nodes refused it
  const auto found = model.scenes[std::size_t(s)].extensions.find(kExtension);
  if (found == model.scenes[std::size_t(s)].extensions.end()) return std::nullopt;
  const tinygltf::Value& index = member(found->second, "light");
  return index.IsInt() ? std::optional<int>(index.Get<int>()) : std::optional<int>(-1);
}

} // namespace

std::optional<sky::Sky> image_based_sky(const tinygltf::Model& model, const Context& ctx) {
  const std::optional<int> index = named_light(model);
  if (!index) return std::nullopt;
  const std::string place = fmt::format("extensions.{}.lights[{}]", kExtension, *index);
  const auto root = model.extensions.find(kExtension);
  const tinygltf::Value& lights = root == model.extensions.end() ? tinygltf::Value() : member(root->second, "lights");
  if (*index < 0 || !lights.IsArray() || std::size_t(*index) >= lights.ArrayLen())
    ctx.fail(place, "the scene's image-based light does not exist");
  const tinygltf::Value& light = lights.Get(*index);
  const std::array<glm::vec3, 9> coefficients = radiance_coefficients(light, place, ctx);
  const glm::quat to_environment = glm::inverse(rotation_of(light, place, ctx));
  const tinygltf::Value& intensity_value = member(light, "intensity");
  const float intensity =
      intensity_value.Type() == tinygltf::NULL_TYPE ? 1.0f : finite_number(intensity_value, place + ".intensity", ctx);
  if (intensity < 0.0f) ctx.fail(place + ".intensity", "is negative");
  sky::EquirectMap map{sky::kEnvironmentWidth, sky::kEnvironmentHeight, {}};
  map.texels.reserve(std::size_t(map.width) * std::size_t(map.height));
  for (int j = 0; j < map.height; ++j)
    for (int i = 0; i < map.width; ++i) {
      const std::array<float, 9> y = sh_basis(to_environment * sky::texel_direction(map.width, map.height, i, j));
      glm::vec3 radiance(0.0f);
      for (std::size_t k = 0; k < 9; ++k) radiance += coefficients[k] * y[k];
      map.texels.push_back(glm::max(radiance * intensity, glm::vec3(0.0f)));
    }
  return sky::Sky{glm::vec3(1.0f), std::move(map), gpu::SKY_KIND_ENVIRONMENT, std::nullopt, {}};
}

} // namespace probebake::scene::detail
