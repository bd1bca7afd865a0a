#include "probebake/dynamic/animation.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace probebake::dynamic {

std::optional<Animation> parse_animation(std::string_view name) {
  if (name == "thesis") return Animation::thesis;
  if (name == "revolution") return Animation::revolution;
  if (name == "soak") return Animation::soak;
  return std::nullopt;
}

const char* to_string(Animation animation) {
  switch (animation) {
  case Animation::thesis: return "thesis";
  case Animation::revolution: return "revolution";
  case Animation::soak: return "soak";
  }
  return "?";
}

int default_frames(Animation animation) { return animation == Animation::soak ? 10000 : 600; }

namespace {

constexpr int kSoakBlock = 10000, kSoakStill = 50;

// Sum of three sines of incommensurate periods with phases from `seed`, in [-1, 1]; 0 while still.
float soak_wave(int frame, int seed, int channel) {
  const int f = frame < 0 ? 0 : frame % kSoakBlock;
  if (f < kSoakStill || f >= kSoakBlock - kSoakStill) return 0.0f;
  const float ramp = std::min(1.0f, float(std::min(f - kSoakStill, kSoakBlock - kSoakStill - f)) / 100.0f);
  constexpr float kPeriods[3] = {97.0f, 233.0f, 611.0f};
  float sum = 0.0f;
  for (int k = 0; k < 3; ++k) {
    const unsigned h = 2654435761u * unsigned(seed * 7 + channel * 3 + k + 1);
    const float phase = float(h >> 8) * (6.2831853f / 16777216.0f);
    sum += std::sin(6.2831853f * float(f) / kPeriods[k] + phase);
  }
  return ramp * sum / 3.0f;
}

} // namespace

float animation_angle(Animation animation, int frame, int seed) {
  if (animation == Animation::soak) return glm::radians(180.0f) * soak_wave(frame, seed, 0);
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

WorldBox world_box(const gpu::DynamicObject& object, const glm::mat4& pose) {
  WorldBox box{glm::vec3(3.4e38f), glm::vec3(-3.4e38f)};
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? object.upper.x : object.lower.x, (c & 2) ? object.upper.y : object.lower.y,
                      (c & 4) ? object.upper.z : object.lower.z);
    const glm::vec3 w = glm::vec3(pose * glm::vec4(p, 1.0f));
    box.min = glm::min(box.min, w);
    box.max = glm::max(box.max, w);
  }
  return box;
}

glm::mat4 animated_pose(Animation animation, int frame, const gpu::DynamicObject& object) {
  const glm::mat4 rest = rest_pose(object);
  const glm::vec3 pivot = glm::vec3(rest * glm::vec4(0.5f * (object.lower + object.upper), 1.0f));
  glm::vec3 shift(0.0f);
  if (animation == Animation::soak) {
    const float reach = glm::length(object.upper - object.lower) / 3.0f;
    shift = reach * glm::vec3(soak_wave(frame, object.gltf_node, 1), 0.0f, soak_wave(frame, object.gltf_node, 2));
  }
  const glm::mat4 turn =
      glm::translate(glm::mat4(1.0f), pivot + shift) *
      glm::rotate(glm::mat4(1.0f), animation_angle(animation, frame, object.gltf_node), glm::vec3(0.0f, 1.0f, 0.0f)) *
      glm::translate(glm::mat4(1.0f), -pivot);
  return turn * rest;
}

} // namespace probebake::dynamic
