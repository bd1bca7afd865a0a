// Scenes with known answers: the white furnace (irradiance pi L / (1 - R) inside a closed emitting box),
// the light-leak pair of rooms, a point light over a plane (E = I cos(theta) / r^2), and the one-triangle
// and empty edge cases.
#include "probebake/samples/scenes.h"

#include <cmath>
#include <string>

namespace probebake::samples {
namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw Error(ErrorKind::usage, message);
}

bool positive(float v) { return std::isfinite(v) && v > 0.0f; }
bool non_negative(float v) { return std::isfinite(v) && v >= 0.0f; }
bool in_unit_range(float v) { return v >= 0.0f && v <= 1.0f; } // false for NaN
bool valid_subdivisions(int s) { return s >= 1 && s <= 1024; }

Light white_point_light(float intensity_candela) {
  Light light;
  light.name = "light";
  light.type = LightType::point;
  light.intensity = intensity_candela;
  return light;
}

} // namespace

SceneBuilder furnace(const FurnaceOptions& options) {
  require(in_unit_range(options.albedo), "furnace: --albedo must be in [0, 1]");
  require(non_negative(options.emission), "furnace: --emission must be finite and >= 0");
  require(positive(options.size), "furnace: --size must be > 0");
  require(valid_subdivisions(options.subdivisions), "furnace: --subdivisions must be in 1..1024");
  SceneBuilder scene("furnace");
  const MaterialId material = scene.add_material({"furnace", glm::vec3(options.albedo), glm::vec3(options.emission)});
  const glm::vec3 half(options.size / 2.0f);
  const MeshId mesh = scene.add_mesh("furnace_box", box(-half, half, Facing::inward, options.subdivisions), material);
  scene.add_mesh_node("furnace_box", mesh);
  return scene;
}

SceneBuilder leak(const LeakOptions& options) {
  require(positive(options.wall_thickness) && options.wall_thickness < 1.0f,
          "leak: --wall-thickness must be in (0, 1) m");
  require(non_negative(options.intensity), "leak: --intensity must be finite and >= 0");
  require(valid_subdivisions(options.subdivisions), "leak: --subdivisions must be in 1..1024");
  SceneBuilder scene("leak");
  const MaterialId white = scene.add_material({"white", glm::vec3(0.8f), {}});
  const float gap = options.wall_thickness / 2.0f; // the rooms' inner faces are the wall's two sides
  const glm::vec3 lit_min(-gap - 3.0f, 0.0f, -1.5f), lit_max(-gap, 2.5f, 1.5f); // 3 x 2.5 x 3 m rooms
  const glm::vec3 dark_min(gap, 0.0f, -1.5f), dark_max(gap + 3.0f, 2.5f, 1.5f);
  scene.add_mesh_node("room_lit",
                      scene.add_mesh("room_lit", box(lit_min, lit_max, Facing::inward, options.subdivisions), white));
  scene.add_mesh_node(
      "room_dark", scene.add_mesh("room_dark", box(dark_min, dark_max, Facing::inward, options.subdivisions), white));
  scene.add_light_node("light", scene.add_light(white_point_light(options.intensity)), (lit_min + lit_max) / 2.0f);
  return scene;
}

SceneBuilder plane_light(const PlaneLightOptions& options) {
  require(positive(options.size), "plane-light: --size must be > 0");
  require(positive(options.height), "plane-light: --height must be > 0");
  require(non_negative(options.intensity), "plane-light: --intensity must be finite and >= 0");
  require(in_unit_range(options.albedo), "plane-light: --albedo must be in [0, 1]");
  require(valid_subdivisions(options.subdivisions), "plane-light: --subdivisions must be in 1..1024");
  SceneBuilder scene("plane-light");
  const MaterialId material = scene.add_material({"plane", glm::vec3(options.albedo), {}});
  const float s = options.size;
  // Edges +Z then +X: cross((0,0,s), (s,0,0)) points along +Y.
  const MeshData plane = quad(glm::vec3(-s / 2.0f, 0.0f, -s / 2.0f), glm::vec3(0.0f, 0.0f, s), glm::vec3(s, 0.0f, 0.0f),
                              options.subdivisions);
  scene.add_mesh_node("plane", scene.add_mesh("plane", plane, material));
  scene.add_light_node("light", scene.add_light(white_point_light(options.intensity)),
                       glm::vec3(0.0f, options.height, 0.0f));
  return scene;
}

SceneBuilder triangle() {
  SceneBuilder scene("triangle");
  const MaterialId white = scene.add_material({"white", glm::vec3(0.8f), {}});
  MeshData mesh;
  mesh.positions = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}}; // counter-clockwise seen from +Y
  mesh.normals.assign(3, glm::vec3(0.0f, 1.0f, 0.0f));
  mesh.indices = {0, 1, 2};
  scene.add_mesh_node("triangle", scene.add_mesh("triangle", mesh, white));
  scene.add_light_node("light", scene.add_light(white_point_light(10.0f)), glm::vec3(0.25f, 1.0f, -0.25f));
  return scene;
}

SceneBuilder empty() { return SceneBuilder("empty"); }

} // namespace probebake::samples
