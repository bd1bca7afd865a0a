// The window room's shell (scene_stiff.cpp's window-room and the courtyard's house).
#include "room_parts.h"

#include <cmath>

namespace probebake::samples::detail {
namespace {

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
  return kept_triangles(box(kRoomMin, kRoomMax, Facing::inward, subdivisions),
                        [](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
                          return !(a.x == kRoomMax.x && b.x == kRoomMax.x && c.x == kRoomMax.x);
                        });
}

} // namespace

MeshData kept_triangles(const MeshData& mesh, const std::function<bool(glm::vec3, glm::vec3, glm::vec3)>& keep) {
  MeshData out;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                    c = mesh.positions[mesh.indices[3 * t + 2]];
    if (!keep(a, b, c)) continue;
    MeshData triangle;
    triangle.positions = {a, b, c};
    triangle.normals.assign(3, mesh.normals[mesh.indices[3 * t]]);
    triangle.indices = {0, 1, 2};
    out.append(triangle);
  }
  return out;
}

MeshData room_with_windows(int windows) {
  MeshData shell = room_without_east_wall(1);
  shell.append(wall_with_windows(windows, 0.5f));
  return shell;
}

} // namespace probebake::samples::detail
