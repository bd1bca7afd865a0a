// The outdoor scene of issue #43: a courtyard open to the sky, lit by `--sky physical` (or any sky) and its sun.
#include "probebake/samples/scenes.h"

#include <string>

#include "room_parts.h"

namespace probebake::samples {

SceneBuilder courtyard(const CourtyardOptions& options) {
  if (!(options.ground_albedo >= 0.0f && options.ground_albedo <= 1.0f))
    throw Error(ErrorKind::usage, "courtyard: --ground-albedo must be in [0, 1]");
  SceneBuilder scene("courtyard");
  const MaterialId ground = scene.add_material({"ground", glm::vec3(options.ground_albedo), {}});
  const MaterialId stone = scene.add_material({"stone", glm::vec3(0.62f, 0.55f, 0.45f), {}});
  const MaterialId brick = scene.add_material({"brick", glm::vec3(0.55f, 0.3f, 0.22f), {}});
  const MaterialId plaster = scene.add_material({"plaster", glm::vec3(0.75f), {}});
  // The house's shell is one surface, seen from inside and outside alike: double-sided.
  const MaterialId house = scene.add_material({"house", glm::vec3(0.7f, 0.68f, 0.6f), {}, true});
  // Ground facing +Y (edges +Z then +X), 40 m square.
  scene.add_mesh_node("ground", scene.add_mesh("ground",
                                               quad(glm::vec3(-20.0f, 0.0f, -20.0f), glm::vec3(0.0f, 0.0f, 40.0f),
                                                    glm::vec3(40.0f, 0.0f, 0.0f), 8),
                                               ground));
  scene.add_mesh_node(
      "west block",
      scene.add_mesh("west block", box({-10.0f, 0.0f, -10.0f}, {-6.0f, 9.0f, 10.0f}, Facing::outward), stone));
  scene.add_mesh_node(
      "east tower",
      scene.add_mesh("east tower", box({6.0f, 0.0f, -10.0f}, {10.0f, 12.0f, -2.0f}, Facing::outward), brick));
  scene.add_mesh_node(
      "north block",
      scene.add_mesh("north block", box({-6.0f, 0.0f, -10.0f}, {6.0f, 6.0f, -6.0f}, Facing::outward), plaster));
  // The window room's shell as a house in the courtyard's south-west, its two windows towards the courtyard (+X).
  Transform at;
  at.translation = glm::vec3(-3.0f, 0.0f, 5.0f);
  scene.add_mesh_node("house", scene.add_mesh("house", detail::room_with_windows(2), house), at);
  return scene;
}

} // namespace probebake::samples
