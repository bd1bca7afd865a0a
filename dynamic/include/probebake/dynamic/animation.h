// The animated tests of the octree thesis, as poses of a volume's dynamic objects per frame: one definition
// shared by the runtime's driver (`probebake run --animate`) and the path-traced reference of a pose
// (`probebake reference --animate`), so that both see the same scene at the same frame.
//
// thesis     (§4.1.3): still until frame 200, then every dynamic object turns 45 degrees about the vertical
//            axis through its centre, at a constant rate until frame 350, then still; 600 frames.
// revolution (Appendix B): a full turn over 150 frames, then 50 still, three times; 600 frames.
// soak       random motion for the long-run test: each object turns and wanders (up to a third of its box
//            size) along a sum of incommensurate sines, its own phases seeded by its glTF node; still in
//            the first and last 50 frames of every block of 10,000 frames, where it is back at rest.
#pragma once

#include <optional>
#include <string_view>

#include <glm/mat4x4.hpp>

#include "probebake/gpu_types.h"

namespace probebake::dynamic {

enum class Animation { thesis, revolution, soak };

std::optional<Animation> parse_animation(std::string_view name); // "thesis", "revolution", "soak"
const char* to_string(Animation animation);
int default_frames(Animation animation); // 600 (thesis, revolution), 10,000 (soak)

// Rotation about the world's vertical (+Y) axis at `frame`, in radians (soak: the object seeded by `seed`).
float animation_angle(Animation animation, int frame, int seed = 0);

// world_from_object at rest (DynamicObject::rest_rows).
glm::mat4 rest_pose(const gpu::DynamicObject& object);

// The world-space box around the object's box under `pose` (its eight corners): where the object is. The
// runtime marks the union of the old and new one as changed; the GPU refit computes the same.
struct WorldBox {
  glm::vec3 min{0.0f}, max{0.0f};
};
WorldBox world_box(const gpu::DynamicObject& object, const glm::mat4& pose);
// The pose at `frame`: the rest pose turned by animation_angle about the vertical axis through the centre
// of the object's box at rest (soak: and moved horizontally).
glm::mat4 animated_pose(Animation animation, int frame, const gpu::DynamicObject& object);

} // namespace probebake::dynamic
