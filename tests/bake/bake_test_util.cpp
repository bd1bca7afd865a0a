#include "bake_test_util.h"

#include <cmath>
#include <random>
#include <utility>

#include <glm/geometric.hpp>

namespace probebake::test {
namespace {

const std::vector<glm::vec3>& random_directions() {
  static const std::vector<glm::vec3> dirs = [] {
    std::mt19937 rng(12345);
    std::normal_distribution<float> normal;
    std::vector<glm::vec3> d;
    while (d.size() < 1024) {
      glm::vec3 v(normal(rng), normal(rng), normal(rng));
      if (glm::length(v) > 1e-3f) d.push_back(glm::normalize(v));
    }
    return d;
  }();
  return dirs;
}

} // namespace

std::filesystem::path write_generated(const samples::SceneBuilder& builder, const std::string& name) {
  const auto dir = std::filesystem::path(PROBEBAKE_BINARY_DIR) / "test-tmp" / "bake";
  std::filesystem::create_directories(dir);
  const auto path = dir / (name + ".glb");
  builder.write_glb(path);
  return path;
}

scene::Scene load_generated(const samples::SceneBuilder& builder, const std::string& name) {
  return scene::load_scene(write_generated(builder, name), {.require_triangles = true});
}

Loaded adopt(scene::Scene s) {
  Loaded l;
  l.scene = std::make_unique<scene::Scene>(std::move(s));
  l.rays = std::make_unique<scene::RayScene>(*l.scene);
  return l;
}

Loaded load(const samples::SceneBuilder& builder, const std::string& name) {
  return adopt(load_generated(builder, name));
}

bool inside_geometry(const scene::RayScene& rays, glm::vec3 p) {
  int hits = 0, back = 0;
  for (const glm::vec3& d : random_directions()) {
    if (auto hit = rays.intersect(p, d)) {
      ++hits;
      back += hit->inside() ? 1 : 0; // the back of a single-sided surface (double-sided: open space)
    }
  }
  return hits > 0 && 2 * back > hits;
}

float nearest_surface(const scene::RayScene& rays, glm::vec3 p) {
  float nearest = INFINITY;
  for (const glm::vec3& d : random_directions())
    if (auto hit = rays.intersect(p, d)) nearest = std::min(nearest, hit->distance);
  return nearest;
}

scene::Scene reversed_double_sided(scene::Scene s) {
  for (glm::uvec3& t : s.triangles) std::swap(t.y, t.z);
  for (scene::Material& m : s.materials) m.double_sided = true;
  return s;
}

bake::BakeSettings test_settings() {
  bake::BakeSettings s;
  s.max_depth = 3;
  s.surfels_per_probe = 64;
  s.svo_depth = 4;
  return s;
}

} // namespace probebake::test
