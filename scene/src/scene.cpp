#include <cmath>
#include <algorithm>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "probebake/scene/scene.h"
#include "probebake/formats/error.h"

namespace probebake::scene {

void Bounds::extend(const glm::vec3& p) {
  min = glm::min(min, p);
  max = glm::max(max, p);
}

float Bounds::largest_extent() const {
  if (empty()) return 0.0f;
  const glm::vec3 extent = max - min;
  return std::max({extent.x, extent.y, extent.z});
}

float ray_epsilon(const Scene& scene) {
  if (scene.bounds.empty()) return 1e-5f;
  const glm::vec3 far = glm::max(glm::abs(scene.bounds.min), glm::abs(scene.bounds.max));
  return std::max(1e-5f * scene.bounds.largest_extent() + 1e-6f * std::max({far.x, far.y, far.z}), 1e-7f);
}

void Bounds::extend(const Bounds& b) {
  if (b.empty()) return;
  extend(b.min);
  extend(b.max);
}

const std::vector<std::string>& supported_extensions() {
  static const std::vector<std::string> names = {
      "KHR_draco_mesh_compression", "KHR_materials_emissive_strength",
      "KHR_lights_punctual",        "KHR_texture_transform",
      "KHR_mesh_quantization",      "EXT_meshopt_compression",
      "EXT_texture_webp",           "KHR_texture_basisu", // through its fallback image, else the factor (warning)
      "EXT_lights_image_based",                           // its irradiance, as the sky
  };
  return names;
}

double triangle_area(const Scene& scene, std::size_t t) {
  const glm::uvec3 tri = scene.triangles[t];
  const glm::dvec3 a(scene.positions[tri.x]), b(scene.positions[tri.y]), c(scene.positions[tri.z]);
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

bool is_double_sided(const Scene& scene, std::size_t t) {
  return scene.materials[scene.triangle_material[t]].double_sided;
}

Scene posed(const Scene& scene, std::span<const glm::mat4> world_from_object) {
  if (world_from_object.size() != scene.dynamic_objects.size())
    throw Error(ErrorKind::internal, "posed: one pose per dynamic object is needed");
  std::vector<glm::mat4> moves; // rest -> pose, in world space
  for (std::size_t o = 0; o < world_from_object.size(); ++o)
    moves.push_back(world_from_object[o] * glm::inverse(scene.dynamic_objects[o].world_from_object));
  Scene out = scene;
  std::vector<bool> moved(scene.positions.size(), false); // a vertex is moved once, whatever shares it
  for (const Instance& instance : scene.instances) {
    if (instance.dynamic_object < 0) continue;
    const glm::mat4& move = moves[std::size_t(instance.dynamic_object)];
    for (std::uint32_t t = instance.first_triangle; t < instance.first_triangle + instance.triangle_count; ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = scene.triangles[t][k];
        if (moved[v]) continue;
        moved[v] = true;
        out.positions[v] = glm::vec3(move * glm::vec4(scene.positions[v], 1.0f));
      }
  }
  out.bounds = Bounds{};
  for (const glm::vec3& p : out.positions) out.bounds.extend(p);
  return out;
}

ReceivingSides receiving_sides(const Scene& scene) {
  ReceivingSides out;
  for (std::uint32_t t = 0; t < scene.triangles.size(); ++t) {
    const double area = triangle_area(scene, t);
    if (!(area > 0.0)) continue;
    for (const bool back : {false, true}) {
      if (back && !is_double_sided(scene, t)) break;
      out.total_area += area;
      out.sides.push_back({t, back});
      out.cumulative_area.push_back(out.total_area);
    }
  }
  return out;
}

glm::vec3 triangle_normal(const Scene& scene, std::size_t t) {
  // In double: the squared length of a float cross product overflows for edges above ~1e9 m and
  // underflows below ~1e-10 m, which left non-unit normals in the file at extreme scales.
  const glm::uvec3 tri = scene.triangles[t];
  const glm::dvec3 a(scene.positions[tri.x]), b(scene.positions[tri.y]), c(scene.positions[tri.z]);
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double len = glm::length(n);
  return len > 0.0 && std::isfinite(len) ? glm::vec3(n / len) : glm::vec3(0.0f);
}

SceneSummary summarize(const Scene& scene) {
  SceneSummary s;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const double area = triangle_area(scene, t);
    if (area <= 0.0) ++s.degenerate_triangles;
    const glm::vec3 e = scene.triangle_emission[t];
    if (e.x > 0.0f || e.y > 0.0f || e.z > 0.0f) {
      ++s.emissive_triangles;
      s.emissive_area += area;
    }
  }
  for (const Instance& i : scene.instances) s.dynamic_instances += i.dynamic ? 1 : 0;
  return s;
}

void set_sky(Scene& scene, sky::Sky sky) {
  if (scene.sun_light >= 0 && std::size_t(scene.sun_light) < scene.lights.size())
    scene.lights.erase(scene.lights.begin() + scene.sun_light);
  scene.sun_light = -1;
  if (sky.physical) {
    const glm::vec3 irradiance = sky::sun_irradiance(*sky.physical);
    const float intensity = std::max({irradiance.x, irradiance.y, irradiance.z});
    Light sun;
    sun.name = "probebake sun";
    sun.type = LightType::directional;
    sun.intensity = intensity;
    sun.color = intensity > 0.0f ? irradiance / intensity : glm::vec3(1.0f);
    sun.direction = -glm::normalize(sky.physical->sun_direction);
    scene.sun_light = int(scene.lights.size());
    scene.lights.push_back(sun);
  }
  if (!sky.source.empty()) {
    std::error_code ec;
    scene.input_files.push_back(std::filesystem::weakly_canonical(sky.source, ec));
  }
  scene.sky = std::move(sky);
}

} // namespace probebake::scene
