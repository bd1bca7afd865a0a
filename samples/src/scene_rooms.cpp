// A large procedural scene for scale tests: a grid of closed rooms with furniture (with --windows, windows in the
// walls that face out of the grid). Deterministic: a
// SplitMix64 generator per room (std:: distributions differ between standard libraries), seeded from
// the scene seed and the room index.
#include "probebake/samples/scenes.h"

#include "room_parts.h"

#include <glm/gtc/matrix_transform.hpp>

#include <array>
#include <cmath>
#include <optional>
#include <string>

namespace probebake::samples {
namespace {

constexpr glm::vec3 room_size{6.0f, 3.0f, 6.0f}; // inside; rooms span x, z in [-3, 3], y in [0, 3]
constexpr float wall_thickness = 0.2f;
constexpr int shell_subdivisions = 24;
constexpr int rug_subdivisions = 16;
constexpr int spheres_per_room = 6;
constexpr int sphere_colours = 4;

class Random {
public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() { // SplitMix64 (Steele, Lea, Flood 2014)
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  float uniform(float lo, float hi) {
    const float unit = static_cast<float>(next() >> 40) / 16777216.0f; // 24 random bits in [0, 1)
    return lo + (hi - lo) * unit;
  }
  int below(int n) { return static_cast<int>(next() % static_cast<std::uint64_t>(n)); }

private:
  std::uint64_t state_;
};

struct Palette {
  MaterialId wall, wood, fabric, panel;
  std::array<MaterialId, sphere_colours> spheres;
};

struct SharedMeshes {
  MeshId shell, panel;
  std::array<MeshId, sphere_colours> spheres;
  std::array<std::optional<MeshId>, 16> shells_with_windows; // by outer_walls() mask, made when first used
};

// Which walls of a room face out of the grid: bit 0 -X, 1 +X, 2 -Z, 3 +Z.
int outer_walls(int room, int count, int columns) {
  const int column = room % columns, row = room / columns, rows = (count + columns - 1) / columns;
  // The last row may be short: a room with no room behind it in +Z, or beside it in +X, faces out there.
  const bool last_in_row = column == columns - 1 || room + 1 >= count;
  return (column == 0 ? 1 : 0) | (last_in_row ? 2 : 0) | (row == 0 ? 4 : 0) |
         (row == rows - 1 || room + columns >= count ? 8 : 0);
}

// The shell with a window in each wall of `walls` (outer_walls' bits): the cells of the subdivided wall whose centre
// lies within 1.5 m of the wall's middle and 1-2 m high are left out (they fall on the 0.25 x 0.125 m cells' edges).
MeshData shell_with_windows(int walls) {
  const glm::vec3 lo(-room_size.x / 2.0f, 0.0f, -room_size.z / 2.0f), hi = lo + room_size;
  return detail::kept_triangles(
      box(lo, hi, Facing::inward, shell_subdivisions), [walls](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        const glm::vec3 centre = (a + b + c) / 3.0f;
        const bool x_wall = a.x == b.x && b.x == c.x, z_wall = a.z == b.z && b.z == c.z;
        const int wall = x_wall ? (a.x < 0.0f ? 1 : 2) : z_wall ? (a.z < 0.0f ? 4 : 8) : 0;
        const float along = x_wall ? centre.z : centre.x;
        return (walls & wall) == 0 || !(centre.y > 1.0f && centre.y < 2.0f && std::abs(along) < 1.5f);
      });
}

Palette add_palette(SceneBuilder& scene) {
  Palette p;
  p.wall = scene.add_material({"wall", {0.8f, 0.78f, 0.75f}, {}});
  p.wood = scene.add_material({"wood", {0.45f, 0.3f, 0.18f}, {}});
  p.fabric = scene.add_material({"fabric", {0.5f, 0.1f, 0.1f}, {}});
  p.panel = scene.add_material({"panel", glm::vec3(0.8f), glm::vec3(10.0f)});
  const std::array<glm::vec3, sphere_colours> colours{
      {{0.9f, 0.9f, 0.9f}, {0.2f, 0.4f, 0.8f}, {0.8f, 0.6f, 0.1f}, {0.2f, 0.6f, 0.3f}}};
  for (int c = 0; c < sphere_colours; ++c) {
    p.spheres[static_cast<std::size_t>(c)] =
        scene.add_material({"sphere_" + std::to_string(c), colours[static_cast<std::size_t>(c)], {}});
  }
  return p;
}

SharedMeshes add_shared_meshes(SceneBuilder& scene, const Palette& palette, int detail) {
  SharedMeshes m;
  const glm::vec3 lo(-room_size.x / 2.0f, 0.0f, -room_size.z / 2.0f);
  m.shell = scene.add_mesh("room_shell", box(lo, lo + room_size, Facing::inward, shell_subdivisions), palette.wall);
  // 0.8 m square 1 cm under the ceiling, facing down: cross(+X, +Z) = -Y.
  const MeshData panel =
      quad(glm::vec3(-0.4f, room_size.y - 0.01f, -0.4f), glm::vec3(0.8f, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, 0.8f));
  m.panel = scene.add_mesh("ceiling_panel", panel, palette.panel);
  const MeshData sphere = cube_sphere(detail);
  for (int c = 0; c < sphere_colours; ++c) {
    m.spheres[static_cast<std::size_t>(c)] =
        scene.add_mesh("sphere_" + std::to_string(c), sphere, palette.spheres[static_cast<std::size_t>(c)]);
  }
  return m;
}

MeshData solid(glm::vec3 lo, glm::vec3 hi) { return box(lo, hi, Facing::outward); }

// A chair in its own frame: seat centred on the origin, backrest towards +X. 6 boxes.
MeshData chair() {
  MeshData mesh = solid({-0.22f, 0.43f, -0.22f}, {0.22f, 0.47f, 0.22f});
  mesh.append(solid({0.18f, 0.47f, -0.22f}, {0.22f, 0.95f, 0.22f}));
  for (float x : {-0.19f, 0.19f}) {
    for (float z : {-0.19f, 0.19f}) mesh.append(solid({x - 0.02f, 0.0f, z - 0.02f}, {x + 0.02f, 0.43f, z + 0.02f}));
  }
  return mesh;
}

// Table (5 boxes) and four chairs (two each side, facing it), in the table's frame.
MeshData dining_set() {
  MeshData mesh = solid({-0.8f, 0.72f, -0.45f}, {0.8f, 0.77f, 0.45f});
  for (float x : {-0.72f, 0.72f}) {
    for (float z : {-0.37f, 0.37f}) mesh.append(solid({x - 0.03f, 0.0f, z - 0.03f}, {x + 0.03f, 0.72f, z + 0.03f}));
  }
  const MeshData one_chair = chair();
  for (float z : {-0.25f, 0.25f}) {
    mesh.append(transformed(one_chair, glm::translate(glm::mat4(1.0f), {1.15f, 0.0f, z})));
    const glm::mat4 facing_back = glm::rotate(glm::mat4(1.0f), 3.14159265f, glm::vec3(0.0f, 1.0f, 0.0f));
    mesh.append(transformed(one_chair, glm::translate(glm::mat4(1.0f), {-1.15f, 0.0f, z}) * facing_back));
  }
  return mesh;
}

// A 2 m wide, 1.8 m tall bookshelf against the back wall (z = -3), centred at x: 2 sides + 4 boards.
MeshData shelf(float x) {
  const float back = -room_size.z / 2.0f + 0.05f;
  const float front = back + 0.35f;
  MeshData mesh;
  for (float side : {x - 1.0f, x + 0.96f}) mesh.append(solid({side, 0.0f, back}, {side + 0.04f, 1.8f, front}));
  for (float y : {0.05f, 0.6f, 1.2f, 1.76f}) mesh.append(solid({x - 0.96f, y, back}, {x + 0.96f, y + 0.04f, front}));
  return mesh;
}

MeshId add_furniture(SceneBuilder& scene, const Palette& palette, Random& random, int room) {
  const glm::vec3 jitter(random.uniform(-0.2f, 0.2f), 0.0f, random.uniform(-0.2f, 0.2f));
  const glm::mat4 table_frame =
      glm::rotate(glm::translate(glm::mat4(1.0f), jitter), random.uniform(-0.4f, 0.4f), glm::vec3(0.0f, 1.0f, 0.0f));
  MeshData wood = transformed(dining_set(), table_frame);
  wood.append(shelf(random.uniform(-0.5f, 0.5f)));
  // A 3 x 2 m rug 5 mm above the floor, facing up: cross(+Z, +X) = +Y.
  const MeshData rug =
      transformed(quad({-1.5f, 0.005f, -1.0f}, {0.0f, 0.0f, 2.0f}, {3.0f, 0.0f, 0.0f}, rug_subdivisions), table_frame);
  std::vector<Primitive> primitives;
  primitives.push_back(Primitive{std::move(wood), palette.wood});
  primitives.push_back(Primitive{rug, palette.fabric});
  const std::string name = "room_" + std::to_string(room) + "_furniture";
  return scene.add_mesh(name, std::move(primitives));
}

void add_spheres(SceneBuilder& scene, const SharedMeshes& meshes, Random& random, int room, NodeId parent) {
  for (int s = 0; s < spheres_per_room; ++s) {
    const float side = (s % 2 == 0) ? -1.0f : 1.0f;
    const float z = -2.0f + 2.0f * static_cast<float>(s / 2);
    Transform t;
    const float radius = random.uniform(0.2f, 0.45f);
    t.scale = glm::vec3(radius);
    t.translation = glm::vec3(side * 2.3f + random.uniform(-0.1f, 0.1f), radius, z + random.uniform(-0.15f, 0.15f));
    const MeshId mesh = meshes.spheres[static_cast<std::size_t>(random.below(sphere_colours))];
    const NodeId node =
        scene.add_mesh_node("room_" + std::to_string(room) + "_sphere_" + std::to_string(s), mesh, t, parent);
    if (s == 0) scene.set_dynamic(node); // one moving object per room
  }
}

void add_room(SceneBuilder& scene, const Palette& palette, SharedMeshes& meshes, const RoomsOptions& options, int room,
              int columns) {
  Random random(static_cast<std::uint64_t>(options.seed) * 0x100000001B3ull + static_cast<std::uint64_t>(room));
  const std::string prefix = "room_" + std::to_string(room);
  const float pitch_x = room_size.x + wall_thickness;
  const float pitch_z = room_size.z + wall_thickness;
  Transform placement;
  placement.translation =
      glm::vec3(static_cast<float>(room % columns) * pitch_x, 0.0f, static_cast<float>(room / columns) * pitch_z);
  const NodeId node = scene.add_node(prefix, placement);
  MeshId shell = meshes.shell;
  if (const int walls = outer_walls(room, options.count, columns); options.windows && walls != 0) {
    std::optional<MeshId>& windowed = meshes.shells_with_windows[std::size_t(walls)];
    if (!windowed)
      windowed = scene.add_mesh("room_shell_windows_" + std::to_string(walls), shell_with_windows(walls), palette.wall);
    shell = *windowed;
  }
  scene.add_mesh_node(prefix + "_shell", shell, {}, node);
  scene.add_mesh_node(prefix + "_furniture", add_furniture(scene, palette, random, room), {}, node);
  add_spheres(scene, meshes, random, room, node);
  Light light;
  light.name = prefix + "_light";
  light.intensity = random.uniform(40.0f, 160.0f);
  light.range = options.light_range;
  light.color = glm::vec3(1.0f, random.uniform(0.8f, 1.0f), random.uniform(0.6f, 1.0f));
  const glm::vec3 light_position(random.uniform(-0.5f, 0.5f), 2.6f, random.uniform(-0.5f, 0.5f));
  scene.add_light_node(prefix + "_light", scene.add_light(light), light_position, {0.0f, -1.0f, 0.0f}, node);
  if (room % 3 == 0) {
    Transform panel;
    panel.translation = glm::vec3(1.5f, 0.0f, 1.5f);
    scene.add_mesh_node(prefix + "_panel", meshes.panel, panel, node);
  }
}

} // namespace

SceneBuilder rooms(const RoomsOptions& options) {
  if (options.count < 1 || options.count > 4096) throw Error(ErrorKind::usage, "rooms: --count must be in 1..4096");
  if (options.detail < 1 || options.detail > 256) throw Error(ErrorKind::usage, "rooms: --detail must be in 1..256");
  if (!(options.light_range >= 0.0f && std::isfinite(options.light_range)))
    throw Error(ErrorKind::usage, "rooms: --light-range must be finite and >= 0");
  SceneBuilder scene("rooms");
  const Palette palette = add_palette(scene);
  SharedMeshes meshes = add_shared_meshes(scene, palette, options.detail);
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(options.count))));
  for (int room = 0; room < options.count; ++room) add_room(scene, palette, meshes, options, room, columns);
  return scene;
}

} // namespace probebake::samples
