// The window room's shell, shared by the window-room and the courtyard's house.
#pragma once

#include <functional>

#include "probebake/samples/geometry.h"

namespace probebake::samples::detail {

inline constexpr glm::vec3 kRoomMin{-2.0f, 0.0f, -2.0f}, kRoomMax{2.0f, 2.5f, 2.0f}; // 4 x 2.5 x 4 m inside

// The room's six faces facing in, its +X wall (x = 2) of 0.5 m cells with `windows` (1..4) of them left out
// 1.0..1.5 m high.
MeshData room_with_windows(int windows);

// The triangles of `mesh` whose corners pass keep(a, b, c), each with its own three vertices (walls cut open).
MeshData kept_triangles(const MeshData& mesh, const std::function<bool(glm::vec3, glm::vec3, glm::vec3)>& keep);

} // namespace probebake::samples::detail
