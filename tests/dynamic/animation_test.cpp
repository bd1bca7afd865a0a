// The animated tests' poses (dynamic/animation.h): the thesis's and Appendix B's angles at the frames the
// texts name, rest poses exactly where the motion is still, and rigid motions about a fixed pivot.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "probebake/dynamic/animation.h"

namespace probebake::dynamic {
namespace {

gpu::DynamicObject box_at(glm::vec3 offset) {
  gpu::DynamicObject o{};
  o.lower = glm::vec3(-0.1f, 0.0f, -0.2f);
  o.upper = glm::vec3(0.3f, 0.5f, 0.2f);
  o.gltf_node = 7;
  o.rest_rows[0] = glm::vec4(1.0f, 0.0f, 0.0f, offset.x);
  o.rest_rows[1] = glm::vec4(0.0f, 1.0f, 0.0f, offset.y);
  o.rest_rows[2] = glm::vec4(0.0f, 0.0f, 1.0f, offset.z);
  return o;
}

TEST(Animation, ThesisTurnsFortyFiveDegreesFromFrame200To350) {
  EXPECT_EQ(animation_angle(Animation::thesis, 0), 0.0f);
  EXPECT_EQ(animation_angle(Animation::thesis, 200), 0.0f);
  EXPECT_NEAR(animation_angle(Animation::thesis, 275), glm::radians(22.5f), 1e-6f);
  EXPECT_NEAR(animation_angle(Animation::thesis, 350), glm::radians(45.0f), 1e-6f);
  EXPECT_NEAR(animation_angle(Animation::thesis, 599), glm::radians(45.0f), 1e-6f);
}

TEST(Animation, RevolutionTurnsOnceIn150FramesThenRests50ThreeTimes) {
  EXPECT_NEAR(animation_angle(Animation::revolution, 75), glm::radians(180.0f), 1e-5f);
  EXPECT_NEAR(animation_angle(Animation::revolution, 275), glm::radians(180.0f), 1e-5f);
  for (int f : {0, 150, 199, 200, 350, 599}) EXPECT_EQ(animation_angle(Animation::revolution, f), 0.0f) << f;
  const gpu::DynamicObject o = box_at({1.0f, 2.0f, 3.0f});
  EXPECT_EQ(animated_pose(Animation::revolution, 170, o), rest_pose(o)); // exactly the rest pose
}

TEST(Animation, TurnsAboutTheVerticalAxisThroughTheBoxCentre) {
  const gpu::DynamicObject o = box_at({1.0f, 2.0f, 3.0f});
  const glm::vec4 centre(0.5f * (o.lower + o.upper), 1.0f);
  const glm::vec3 pivot = glm::vec3(rest_pose(o) * centre);
  for (int f : {0, 260, 350, 500}) {
    const glm::mat4 m = animated_pose(Animation::thesis, f, o);
    EXPECT_LT(glm::length(glm::vec3(m * centre) - pivot), 1e-5f) << f;
    EXPECT_NEAR(glm::determinant(glm::mat3(m)), 1.0f, 1e-5f);
    EXPECT_NEAR(m[1][1], 1.0f, 1e-6f); // the vertical axis stays vertical
  }
  // At 350 a point level with the centre has turned 45 degrees about the pivot.
  const glm::vec4 side = centre + glm::vec4(0.2f, 0.0f, 0.0f, 0.0f);
  const glm::vec3 corner = glm::vec3(animated_pose(Animation::thesis, 350, o) * side) - pivot;
  const glm::vec3 rest_corner = glm::vec3(rest_pose(o) * side) - pivot;
  EXPECT_NEAR(glm::dot(glm::normalize(corner), glm::normalize(rest_corner)), std::cos(glm::radians(45.0f)), 1e-5f);
}

TEST(Animation, SoakWandersBoundedAndEndsEveryBlockAtRest) {
  const gpu::DynamicObject o = box_at({0.0f, 0.0f, 0.0f});
  const float reach = glm::length(o.upper - o.lower) / 3.0f;
  const glm::vec4 centre(0.5f * (o.lower + o.upper), 1.0f);
  float farthest = 0.0f;
  for (int f = 0; f < 10000; f += 7) {
    const glm::mat4 m = animated_pose(Animation::soak, f, o);
    farthest = std::max(farthest, glm::length(glm::vec3(m * centre - centre)));
    EXPECT_NEAR(glm::determinant(glm::mat3(m)), 1.0f, 1e-4f);
  }
  EXPECT_GT(farthest, 0.2f * reach); // it does move
  EXPECT_LE(farthest, reach * std::sqrt(2.0f) + 1e-5f);
  for (int f : {0, 49, 9950, 9999, 10000, 10049}) EXPECT_EQ(animated_pose(Animation::soak, f, o), rest_pose(o)) << f;
  EXPECT_NE(animation_angle(Animation::soak, 3000, 1), animation_angle(Animation::soak, 3000, 2)); // own phases
}

TEST(Animation, NamesRoundTrip) {
  for (Animation a : {Animation::thesis, Animation::revolution, Animation::soak})
    EXPECT_EQ(parse_animation(to_string(a)), a);
  EXPECT_FALSE(parse_animation("spin").has_value());
  EXPECT_EQ(default_frames(Animation::soak), 10000);
}

} // namespace
} // namespace probebake::dynamic
