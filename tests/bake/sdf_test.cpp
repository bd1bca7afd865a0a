// SceneSdf: signs of closed solids and rooms, open meshes, distances, gradients, push_out, determinism
// across builds and thread counts, and that nothing returns NaN.
#include "probebake/placement/scene_sdf.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>
#include <utility>
#include <vector>

namespace pb = probebake::placement;
using probebake::scene::Scene;

namespace {

// Appends an axis-aligned box [lo, hi] as 12 triangles; normals point out (a solid) or in (a room).
void add_box(Scene& scene, glm::vec3 lo, glm::vec3 hi, bool normals_in) {
  const auto base = static_cast<unsigned>(scene.positions.size());
  for (int i = 0; i < 8; ++i)
    scene.positions.emplace_back(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  // Two CCW-from-outside triangles per face, corners indexed by bit (x=1, y=2, z=4).
  const unsigned quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    glm::uvec3 a(base + q[0], base + q[1], base + q[2]), b(base + q[0], base + q[2], base + q[3]);
    if (normals_in) {
      std::swap(a.y, a.z);
      std::swap(b.y, b.z);
    }
    scene.triangles.push_back(a);
    scene.triangles.push_back(b);
  }
  for (const glm::vec3& p : scene.positions) scene.bounds.extend(p);
}

Scene unit_cube() {
  Scene scene;
  add_box(scene, glm::vec3(0.0f), glm::vec3(1.0f), false);
  return scene;
}

Scene room(bool with_cube) {
  Scene scene;
  add_box(scene, glm::vec3(0.0f), glm::vec3(4.0f), true);
  if (with_cube) add_box(scene, glm::vec3(1.5f), glm::vec3(2.5f), false);
  return scene;
}

// Gives every triangle from `first` on a material of its own kind: the scene's materials become
// {single-sided, double-sided} (hand-built scenes have none, which reads as single-sided).
void mark_double_sided(Scene& scene, std::size_t first) {
  if (scene.materials.empty()) {
    scene.materials.resize(2);
    scene.materials[1].double_sided = true;
  }
  scene.triangle_material.resize(scene.triangles.size(), 0);
  for (std::size_t t = first; t < scene.triangles.size(); ++t) scene.triangle_material[t] = 1;
}

// The room's walls wound the wrong way (normals out, as a solid box) but double-sided: by the glTF
// rule the same room as room(false), which must be free space inside, not a solid.
Scene reversed_double_sided_room(bool with_cube) {
  Scene scene;
  add_box(scene, glm::vec3(0.0f), glm::vec3(4.0f), false);
  mark_double_sided(scene, 0);
  if (with_cube) {
    add_box(scene, glm::vec3(1.5f), glm::vec3(2.5f), false); // single-sided solid
    scene.triangle_material.resize(scene.triangles.size(), 0);
  }
  return scene;
}

// 0.02 voxels, band 0.4: wide enough to see 0.3 outside a face unclamped.
const pb::SdfSettings cube_settings{0.02f, 20.0f};
const pb::SdfSettings room_settings{0.05f, 8.0f};

const glm::vec3 face_normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::vector<glm::vec3> sample_points(glm::vec3 lo, glm::vec3 hi, int n) {
  std::vector<glm::vec3> points;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        points.push_back(lo + (hi - lo) * (glm::vec3(float(i), float(j), float(k)) + 0.37f) / float(n));
  return points;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

} // namespace

TEST(SceneSdf, CubeCentreIsInsideAtHalfAUnit) {
  const pb::SceneSdf sdf(unit_cube(), cube_settings);
  EXPECT_NEAR(sdf.distance(glm::vec3(0.5f)), -0.5f, sdf.voxel_size());
  EXPECT_NEAR(sdf.distance(glm::vec3(0.5f, 0.5f, 0.9f)), -0.1f, sdf.voxel_size());
}

TEST(SceneSdf, OutsideEachFaceDistanceAndGradientFollowTheNormal) {
  const pb::SceneSdf sdf(unit_cube(), cube_settings);
  for (const glm::vec3& n : face_normals) {
    const glm::vec3 p = glm::vec3(0.5f) + n * 0.8f; // 0.3 from the face
    EXPECT_NEAR(sdf.distance(p), 0.3f, sdf.voxel_size()) << n.x << n.y << n.z;
    EXPECT_GT(glm::dot(sdf.gradient(p), n), 0.99f);
    // Inside, near the same face, the gradient also points out through it.
    EXPECT_GT(glm::dot(sdf.gradient(glm::vec3(0.5f) + n * 0.4f), n), 0.99f);
  }
}

TEST(SceneSdf, GradientIsUnitOrZero) {
  const pb::SceneSdf sdf(unit_cube(), cube_settings);
  for (const glm::vec3& p : sample_points(glm::vec3(-1.0f), glm::vec3(2.0f), 9)) {
    const float length = glm::length(sdf.gradient(p));
    EXPECT_TRUE(length == 0.0f || std::abs(length - 1.0f) < 1e-4f) << length;
  }
  EXPECT_EQ(sdf.gradient(glm::vec3(10.0f)), glm::vec3(0.0f)); // saturated free space
}

TEST(SceneSdf, ValuesSaturateAtTheBand) {
  const pb::SceneSdf sdf(unit_cube(), cube_settings);
  EXPECT_FLOAT_EQ(sdf.band_width(), 0.4f);
  EXPECT_FLOAT_EQ(sdf.distance(glm::vec3(0.5f, 0.5f, 3.0f)), sdf.band_width());
  EXPECT_FLOAT_EQ(sdf.distance(glm::vec3(1e6f)), sdf.band_width());
}

TEST(SceneSdf, AutomaticVoxelSizeIsDiagonalOver256) {
  const pb::SceneSdf sdf(unit_cube());
  EXPECT_NEAR(sdf.voxel_size(), std::sqrt(3.0f) / 256.0f, 1e-6f);
  EXPECT_NEAR(sdf.band_width(), 3.0f * sdf.voxel_size(), 1e-6f);
  EXPECT_NEAR(sdf.distance(glm::vec3(0.5f)), -0.5f, sdf.voxel_size()); // interior filled at any band
}

TEST(SceneSdf, PushOutFromCubeCentreReachesClearanceDeterministically) {
  const float clearance = 0.1f;
  const pb::SceneSdf a(unit_cube(), cube_settings);
  const pb::SceneSdf b(unit_cube(), cube_settings);
  const auto out_a = a.push_out(glm::vec3(0.5f), clearance);
  const auto out_b = b.push_out(glm::vec3(0.5f), clearance);
  ASSERT_TRUE(out_a.has_value());
  ASSERT_TRUE(out_b.has_value());
  EXPECT_GE(a.distance(*out_a), clearance);
  const glm::vec3 outside = glm::max(glm::vec3(0.0f) - *out_a, *out_a - glm::vec3(1.0f));
  EXPECT_GT(std::max({outside.x, outside.y, outside.z}), clearance - a.voxel_size());
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(same_bits((*out_a)[k], (*out_b)[k]));
}

TEST(SceneSdf, PushOutFromOffCentreLeavesThroughTheNearestFace) {
  const pb::SceneSdf sdf(unit_cube(), cube_settings);
  const auto out = sdf.push_out(glm::vec3(0.5f, 0.8f, 0.45f), 0.05f);
  ASSERT_TRUE(out.has_value());
  EXPECT_GE(sdf.distance(*out), 0.05f);
  EXPECT_NEAR(out->y, 1.05f, 2.0f * sdf.voxel_size());
  EXPECT_NEAR(out->x, 0.5f, 1e-3f);
}

TEST(SceneSdf, PushOutEdgeCases) {
  const pb::SceneSdf sdf(unit_cube(), cube_settings);
  const glm::vec3 clear(0.5f, 0.5f, 2.0f);
  EXPECT_EQ(sdf.push_out(clear, 0.1f), clear);                          // already clear: unchanged
  EXPECT_FALSE(sdf.push_out(glm::vec3(0.5f), sdf.band_width() * 2.0f)); // beyond what the band confirms
  EXPECT_FALSE(sdf.push_out(glm::vec3(0.5f), 0.1f, 3));                 // too few steps
  EXPECT_FALSE(sdf.push_out(glm::vec3(std::numeric_limits<float>::quiet_NaN()), 0.1f));
}

// The inside of the 4 m room: free space beyond the band at its centre, 0.2 at 0.2 from each wall with the
// gradient away from it.
void expect_room_interior_free(const pb::SceneSdf& sdf) {
  EXPECT_FLOAT_EQ(sdf.distance(glm::vec3(2.0f)), sdf.band_width());
  for (const glm::vec3& n : face_normals) {
    const glm::vec3 p = glm::vec3(2.0f) + n * 1.8f; // 0.2 from a wall, inside
    EXPECT_NEAR(sdf.distance(p), 0.2f, sdf.voxel_size());
    EXPECT_GT(glm::dot(sdf.gradient(p), -n), 0.99f); // away from the wall, into the room
  }
}

TEST(SceneSdf, RoomInteriorIsFreeSpace) {
  const pb::SceneSdf sdf(room(false), room_settings);
  expect_room_interior_free(sdf);
  for (const glm::vec3& p : sample_points(glm::vec3(0.1f), glm::vec3(3.9f), 7)) EXPECT_GT(sdf.distance(p), 0.0f);
}

TEST(SceneSdf, SolidInsideARoomIsStillSolid) {
  const pb::SceneSdf sdf(room(true), room_settings);
  EXPECT_NEAR(sdf.distance(glm::vec3(2.0f)), -0.5f, sdf.voxel_size());
  EXPECT_NEAR(sdf.distance(glm::vec3(2.0f, 2.0f, 2.8f)), 0.3f, sdf.voxel_size());
  EXPECT_NEAR(sdf.distance(glm::vec3(0.2f, 2.0f, 2.0f)), 0.2f, sdf.voxel_size());
  // Near the cube's corners and edges (where pseudonormals matter) the room stays free space.
  for (const glm::vec3& p : sample_points(glm::vec3(1.3f), glm::vec3(2.7f), 12)) {
    const bool in_cube = glm::all(glm::greaterThan(p, glm::vec3(1.5f))) && glm::all(glm::lessThan(p, glm::vec3(2.5f)));
    const glm::vec3 gap = glm::max(glm::vec3(1.5f) - p, p - glm::vec3(2.5f));
    const float outside = std::max({gap.x, gap.y, gap.z});
    if (in_cube && outside < -sdf.voxel_size()) {
      EXPECT_LT(sdf.distance(p), 0.0f);
    } else if (!in_cube && outside > sdf.voxel_size()) {
      EXPECT_GT(sdf.distance(p), 0.0f);
    }
  }
  const auto out = sdf.push_out(glm::vec3(2.0f), 0.2f);
  ASSERT_TRUE(out.has_value());
  EXPECT_GE(sdf.distance(*out), 0.2f);
}

TEST(SceneSdf, OpenPlaneHasNoInside) {
  Scene scene;
  scene.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  scene.triangles = {{0, 1, 2}, {0, 2, 3}}; // normal +z
  const pb::SceneSdf sdf(scene, cube_settings);
  EXPECT_NEAR(sdf.distance(glm::vec3(0.5f, 0.5f, 0.2f)), 0.2f, sdf.voxel_size());
  EXPECT_NEAR(sdf.distance(glm::vec3(0.5f, 0.5f, -0.2f)), 0.2f, sdf.voxel_size()); // behind: unsigned
  EXPECT_LT(sdf.gradient(glm::vec3(0.5f, 0.5f, -0.2f)).z, -0.99f);
}

TEST(SceneSdf, DoubleSidedPlaneIsOutsideOnBothSidesAtItsDistance) {
  Scene scene;
  scene.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  scene.triangles = {{0, 1, 2}, {0, 2, 3}}; // normal +z
  mark_double_sided(scene, 0);
  const pb::SceneSdf sdf(scene, cube_settings);
  for (const float z : {0.3f, 0.1f, 0.04f, -0.04f, -0.1f, -0.3f}) {
    EXPECT_NEAR(sdf.distance(glm::vec3(0.5f, 0.5f, z)), std::abs(z), sdf.voxel_size()) << z;
    EXPECT_GT(sdf.gradient(glm::vec3(0.5f, 0.5f, z)).z * z, 0.99f * std::abs(z)) << z; // away from the plane
  }
  // Beside its edge: the distance to the edge, not to the plane's infinite extension.
  EXPECT_NEAR(sdf.distance(glm::vec3(1.3f, 0.5f, 0.0f)), 0.3f, sdf.voxel_size());
  // A probe 0.05 behind it is pushed to the clearance on its own side, not through the plane.
  const auto out = sdf.push_out(glm::vec3(0.5f, 0.5f, -0.05f), 0.2f);
  ASSERT_TRUE(out.has_value());
  EXPECT_NEAR(out->z, -0.2f, 2.0f * sdf.voxel_size());
}

TEST(SceneSdf, ReversedDoubleSidedRoomIsFreeSpaceInside) {
  Scene single;
  add_box(single, glm::vec3(0.0f), glm::vec3(4.0f), false);
  EXPECT_NEAR(pb::SceneSdf(single, room_settings).distance(glm::vec3(2.0f)), -2.0f, 0.05f); // the solid it would be
  const pb::SceneSdf sdf(reversed_double_sided_room(false), room_settings);
  expect_room_interior_free(sdf);
  for (const glm::vec3& n : face_normals) // and 0.2 outside each wall
    EXPECT_NEAR(sdf.distance(glm::vec3(2.0f) + n * 2.2f), 0.2f, sdf.voxel_size());
  for (const glm::vec3& p : sample_points(glm::vec3(-0.5f), glm::vec3(4.5f), 9)) EXPECT_GE(sdf.distance(p), 0.0f);
}

TEST(SceneSdf, SolidInsideADoubleSidedRoomIsStillSolid) {
  const pb::SceneSdf sdf(reversed_double_sided_room(true), room_settings);
  EXPECT_NEAR(sdf.distance(glm::vec3(2.0f)), -0.5f, sdf.voxel_size());
  EXPECT_NEAR(sdf.distance(glm::vec3(2.0f, 2.0f, 2.8f)), 0.3f, sdf.voxel_size());
  EXPECT_NEAR(sdf.distance(glm::vec3(0.2f, 2.0f, 2.0f)), 0.2f, sdf.voxel_size());
  const auto out = sdf.push_out(glm::vec3(2.0f), 0.2f);
  ASSERT_TRUE(out.has_value());
  EXPECT_GE(sdf.distance(*out), 0.2f);
}

TEST(SceneSdf, DoubleSidedPlaneInsideASolidStaysInside) {
  Scene scene = unit_cube();
  const auto base = static_cast<unsigned>(scene.positions.size());
  scene.positions.insert(scene.positions.end(),
                         {{0.1f, 0.1f, 0.5f}, {0.9f, 0.1f, 0.5f}, {0.9f, 0.9f, 0.5f}, {0.1f, 0.9f, 0.5f}});
  scene.triangles.push_back({base, base + 1, base + 2});
  scene.triangles.push_back({base, base + 2, base + 3});
  mark_double_sided(scene, 12);
  const pb::SceneSdf sdf(scene, cube_settings);
  EXPECT_NEAR(sdf.distance(glm::vec3(0.5f, 0.5f, 0.3f)), -0.3f, sdf.voxel_size());
  EXPECT_NEAR(sdf.distance(glm::vec3(0.5f, 0.5f, 0.5f)), -0.5f, sdf.voxel_size()); // on the plane: the solid's depth
}

TEST(SceneSdf, EmptySceneIsFreeSpace) {
  const pb::SceneSdf sdf(Scene{});
  EXPECT_FLOAT_EQ(sdf.distance(glm::vec3(0.0f)), sdf.band_width());
  EXPECT_EQ(sdf.gradient(glm::vec3(0.0f)), glm::vec3(0.0f));
  EXPECT_EQ(sdf.push_out(glm::vec3(1.0f), 0.0f), glm::vec3(1.0f));
}

TEST(SceneSdf, RejectsBadInput) {
  Scene bad = unit_cube();
  bad.triangles.push_back({0, 1, 99});
  EXPECT_THROW(pb::SceneSdf{bad}, std::invalid_argument);
  EXPECT_THROW(pb::SceneSdf(unit_cube(), pb::SdfSettings{-1.0f, 3.0f}), std::invalid_argument);
  EXPECT_THROW(pb::SceneSdf(unit_cube(), pb::SdfSettings{0.0f, 0.5f}), std::invalid_argument);
}

TEST(SceneSdf, NeverNaN) {
  const pb::SceneSdf sdf(room(true), room_settings);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const glm::vec3& p : {glm::vec3(nan), glm::vec3(inf, 0, 0), glm::vec3(-inf), glm::vec3(1e30f)}) {
    EXPECT_FALSE(std::isnan(sdf.distance(p)));
    EXPECT_TRUE(finite(sdf.gradient(p)));
  }
  for (const glm::vec3& p : sample_points(glm::vec3(-1.0f), glm::vec3(5.0f), 10)) {
    EXPECT_TRUE(std::isfinite(sdf.distance(p)));
    EXPECT_TRUE(finite(sdf.gradient(p)));
    if (const auto out = sdf.push_out(p, 0.2f)) {
      EXPECT_TRUE(finite(*out));
    }
  }
}

TEST(SceneSdf, SameValuesForAnyThreadCountAndConcurrentQueries) {
  Scene scene = room(true);
  add_box(scene, glm::vec3(0.5f), glm::vec3(1.0f), false);
  mark_double_sided(scene, 24); // a double-sided box as well: both grids
  const std::vector<glm::vec3> points = sample_points(glm::vec3(-0.5f), glm::vec3(4.5f), 16);
  std::vector<float> serial;
  {
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    const pb::SceneSdf sdf(scene, room_settings);
    for (const glm::vec3& p : points) serial.push_back(sdf.distance(p));
  }
  const pb::SceneSdf sdf(scene, room_settings);
  std::vector<float> parallel(points.size());
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t i = t; i < points.size(); i += 4) parallel[i] = sdf.distance(points[i]);
    });
  for (std::thread& thread : threads) thread.join();
  for (std::size_t i = 0; i < points.size(); ++i) ASSERT_TRUE(same_bits(serial[i], parallel[i])) << i;
}
