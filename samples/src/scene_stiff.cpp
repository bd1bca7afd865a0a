// Stiff scenes of issue #39, each a case that strains the bake or the lookup: a closed room lit only by a
// directional sun through small windows (light enters through a few percent of the walls), a tiny very
// bright emitter, and a closed cavity whose walls reflect 95 % of the light. The Cornell box with a sealed
// emissive light box is `cornell --light-box`.
#include "probebake/samples/scenes.h"

#include <cmath>
#include <string>

namespace probebake::samples {
namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw Error(ErrorKind::usage, message);
}

constexpr glm::vec3 kRoomMin{-2.0f, 0.0f, -2.0f}, kRoomMax{2.0f, 2.5f, 2.0f}; // 4 x 2.5 x 4 m inside

// The room's +X wall (x = 2, facing -X) as cells of `cell` metres, leaving out the windows: the cells whose
// centre lies 1.0..1.5 m high in the first `windows` of these columns along Z.
constexpr int kWindowColumns[4] = {2, 5, 0, 7};
MeshData wall_with_windows(int windows, float cell) {
  const int rows = int(std::lround((kRoomMax.y - kRoomMin.y) / cell));
  const int columns = int(std::lround((kRoomMax.z - kRoomMin.z) / cell)); // 8 for 0.5 m cells
  MeshData wall;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const float y = kRoomMin.y + float(r) * cell, z = kRoomMin.z + float(c) * cell;
      bool window = false;
      for (int w = 0; w < windows; ++w)
        window |= c == kWindowColumns[w] && y + 0.5f * cell > 1.0f && y + 0.5f * cell < 1.5f;
      if (window) continue;
      // Edges +Z then +Y: cross((0,0,1), (0,1,0)) = -X, into the room.
      wall.append(quad(glm::vec3(kRoomMax.x, y, z), glm::vec3(0.0f, 0.0f, cell), glm::vec3(0.0f, cell, 0.0f)));
    }
  return wall;
}

// The room's other five faces, facing in (the box's +X face is dropped).
MeshData room_without_east_wall(int subdivisions) {
  const MeshData full = box(kRoomMin, kRoomMax, Facing::inward, subdivisions);
  MeshData out;
  for (std::size_t t = 0; t < full.triangle_count(); ++t) {
    const glm::vec3 a = full.positions[full.indices[3 * t]], b = full.positions[full.indices[3 * t + 1]],
                    c = full.positions[full.indices[3 * t + 2]];
    if (a.x == kRoomMax.x && b.x == kRoomMax.x && c.x == kRoomMax.x) continue;
    MeshData triangle;
    triangle.positions = {a, b, c};
    triangle.normals.assign(3, full.normals[full.indices[3 * t]]);
    triangle.indices = {0, 1, 2};
    out.append(triangle);
  }
  return out;
}

} // namespace

SceneBuilder window_room(const WindowRoomOptions& options) {
  require(options.windows >= 1 && options.windows <= 4, "window-room: --windows must be in 1..4");
  require(options.albedo >= 0.0f && options.albedo <= 1.0f, "window-room: --albedo must be in [0, 1]");
  require(std::isfinite(options.sun) && options.sun >= 0.0f, "window-room: --sun must be finite and >= 0");
  SceneBuilder scene("window-room");
  const MaterialId wall = scene.add_material({"wall", glm::vec3(options.albedo), {}});
  MeshData shell = room_without_east_wall(1);
  shell.append(wall_with_windows(options.windows, 0.5f));
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
