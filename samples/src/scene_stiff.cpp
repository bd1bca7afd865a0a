// Stiff scenes of issue #39, each a case that strains the bake or the lookup: a closed room lit only by a
// directional sun through small windows (light enters through a few percent of the walls), a tiny very
// bright emitter, and a closed cavity whose walls reflect 95 % of the light. The Cornell box with a sealed
// emissive light box is `cornell --light-box`.
#include "probebake/samples/scenes.h"

#include "room_parts.h"

#include <cmath>
#include <string>

namespace probebake::samples {
using detail::kRoomMax;
using detail::kRoomMin;
namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw Error(ErrorKind::usage, message);
}

} // namespace

SceneBuilder window_room(const WindowRoomOptions& options) {
  require(options.windows >= 1 && options.windows <= 4, "window-room: --windows must be in 1..4");
  require(options.albedo >= 0.0f && options.albedo <= 1.0f, "window-room: --albedo must be in [0, 1]");
  require(std::isfinite(options.sun) && options.sun >= 0.0f, "window-room: --sun must be finite and >= 0");
  SceneBuilder scene("window-room");
  const MaterialId wall = scene.add_material({"wall", glm::vec3(options.albedo), {}});
  MeshData shell = detail::room_with_windows(options.windows);
  scene.add_mesh_node("room", scene.add_mesh("room", shell, wall));
  Light sun;
  sun.name = "sun";
  sun.type = LightType::directional;
  sun.intensity = options.sun;
  // From outside the east wall, 40 degrees down: the windows throw two patches of sun on the floor.
  const glm::vec3 direction = glm::normalize(glm::vec3(-std::cos(0.7f), -std::sin(0.7f), 0.1f));
  scene.add_light_node("sun", scene.add_light(sun), glm::vec3(6.0f, 5.0f, 0.0f), direction);
  return scene;
}

SceneBuilder tiny_emitter(const TinyEmitterOptions& options) {
  require(options.size > 0.0f && options.size < 1.0f, "tiny-emitter: --size must be in (0, 1) m");
  require(std::isfinite(options.radiance) && options.radiance >= 0.0f,
          "tiny-emitter: --radiance must be finite and >= 0");
  SceneBuilder scene("tiny-emitter");
  const MaterialId white = scene.add_material({"white", glm::vec3(0.7f), {}});
  const MaterialId light = scene.add_material({"light", glm::vec3(0.0f), glm::vec3(options.radiance)});
  scene.add_mesh_node("room", scene.add_mesh("room", box(kRoomMin, kRoomMax, Facing::inward), white));
  // A square of side `size` facing down, 1 cm under the ceiling's centre (edges +X then +Z: -Y).
  const float s = options.size;
  scene.add_mesh_node("emitter", scene.add_mesh("emitter",
                                                quad(glm::vec3(-s / 2, kRoomMax.y - 0.01f, -s / 2), glm::vec3(s, 0, 0),
                                                     glm::vec3(0, 0, s)),
                                                light));
  return scene;
}

SceneBuilder cavity(const CavityOptions& options) {
  require(options.albedo >= 0.0f && options.albedo <= 1.0f, "cavity: --albedo must be in [0, 1]");
  SceneBuilder scene("cavity");
  const MaterialId white = scene.add_material({"white", glm::vec3(options.albedo), {}});
  const MaterialId light = scene.add_material({"light", glm::vec3(0.0f), glm::vec3(10.0f)});
  // A closed 1 m box with a block inside and a 10 x 10 cm emitter on the ceiling: all light stays inside,
  // so probe irradiance is bounded by pi L / (1 - albedo) and the bounce iteration contracts by about
  // the albedo per sweep.
  scene.add_mesh_node(
      "box", scene.add_mesh("box", box(glm::vec3(-0.5f, 0, -0.5f), glm::vec3(0.5f, 1, 0.5f), Facing::inward), white));
  scene.add_mesh_node(
      "block",
      scene.add_mesh("block", box(glm::vec3(-0.3f, 0, -0.1f), glm::vec3(0.0f, 0.4f, 0.2f), Facing::outward), white));
  scene.add_mesh_node(
      "emitter",
      scene.add_mesh("emitter", quad(glm::vec3(-0.05f, 0.999f, -0.05f), glm::vec3(0.1f, 0, 0), glm::vec3(0, 0, 0.1f)),
                     light));
  return scene;
}

} // namespace probebake::samples
