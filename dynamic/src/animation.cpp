#include "probebake/dynamic/animation.h"

#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

namespace probebake::dynamic {

std::optional<Animation> parse_animation(std::string_view name) {
  if (name == "thesis") return Animation::thesis;
  if (name == "revolution") return Animation::revolution;
  return std::nullopt;
}

const char* to_string(Animation animation) { return animation == Animation::thesis ? "thesis" : "revolution"; }

int default_frames(Animation) { return 600; }

float animation_angle(Animation animation, int frame) {
  if (animation == Animation::thesis) {
    constexpr int kStart = 200, kEnd = 350;
    const int f = frame < kStart ? kStart : (frame > kEnd ? kEnd : frame);
    return glm::radians(45.0f) * float(f - kStart) / float(kEnd - kStart);
  }
  constexpr int kTurn = 150, kStill = 50;
  const int cycle_frame = frame < 0 ? 0 : frame % (kTurn + kStill);
  // A whole turn is the rest pose: frames of the still part return exactly to it.
  return cycle_frame < kTurn ? glm::radians(360.0f) * float(cycle_frame) / float(kTurn) : 0.0f;
}

glm::mat4 rest_pose(const gpu::DynamicObject& object) {
  glm::mat4 m(1.0f); // glm is column-major: m[column][row]
  for (int row = 0; row < 3; ++row)
    for (int column = 0; column < 4; ++column) m[column][row] = object.rest_rows[row][column];
  return m;
}

glm::mat4 animated_pose(Animation animation, int frame, const gpu::DynamicObject& object) {
  const glm::mat4 rest = rest_pose(object);
  const glm::vec3 pivot = glm::vec3(rest * glm::vec4(0.5f * (object.lower + object.upper), 1.0f));
  const glm::mat4 turn = glm::translate(glm::mat4(1.0f), pivot) *
                         glm::rotate(glm::mat4(1.0f), animation_angle(animation, frame), glm::vec3(0.0f, 1.0f, 0.0f)) *
                         glm::translate(glm::mat4(1.0f), -pivot);
  return turn * rest;
}

} // namespace probebake::dynamic
