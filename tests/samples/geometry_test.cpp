// Procedural meshes: winding, normals, closedness.
#include "probebake/samples/geometry.h"

#include "gltf_readback.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace ps = probebake::samples;
using ps::Facing;

namespace {

std::vector<ps::test::WorldTriangle> triangles_of(const ps::MeshData& mesh) {
  std::vector<ps::test::WorldTriangle> out;
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    out.push_back({mesh.positions[mesh.indices[t]], mesh.positions[mesh.indices[t + 1]],
                   mesh.positions[mesh.indices[t + 2]], 0, ""});
  }
  return out;
}

// Every triangle's winding normal agrees with its stored vertex normals (to within `min_cosine`; smooth
// sphere normals differ from flat ones) and points away from (outward) or towards (inward) `centre`.
void expect_facing(const ps::MeshData& mesh, glm::vec3 centre, Facing facing, float min_cosine = 0.999f) {
  const auto triangles = triangles_of(mesh);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const glm::vec3 n = triangles[t].normal();
    const float away = glm::dot(n, triangles[t].centroid() - centre);
    EXPECT_TRUE(facing == Facing::outward ? away > 0.0f : away < 0.0f) << "triangle " << t;
    for (std::size_t k = 0; k < 3; ++k) EXPECT_GT(glm::dot(n, mesh.normals[mesh.indices[3 * t + k]]), min_cosine);
  }
}

} // namespace

TEST(Geometry, QuadFacesAlongCrossOfEdges) {
  const ps::MeshData q = ps::quad({0, 0, 0}, {0, 0, 2}, {3, 0, 0}, 4);
  EXPECT_EQ(q.triangle_count(), 32u);
  EXPECT_EQ(q.positions.size(), 25u);
  for (const auto& t : triangles_of(q)) EXPECT_NEAR(glm::dot(t.normal(), glm::vec3(0, 1, 0)), 1.0f, 1e-6f);
  const ps::Bounds b = ps::bounds_of(q);
  EXPECT_EQ(b.min, glm::vec3(0, 0, 0));
  EXPECT_EQ(b.max, glm::vec3(3, 0, 2));
}

TEST(Geometry, BoxIsClosedAndFacesTheRightWay) {
  for (int s = 1; s <= 4; ++s) {
    for (Facing facing : {Facing::outward, Facing::inward}) {
      const ps::MeshData b = ps::box({-1, 0, -2}, {1, 3, 2}, facing, s);
      EXPECT_EQ(b.triangle_count(), static_cast<std::size_t>(12 * s * s));
      EXPECT_TRUE(ps::test::is_closed_and_oriented(triangles_of(b))) << "s=" << s;
      expect_facing(b, {0, 1.5f, 0}, facing);
    }
  }
}

TEST(Geometry, CubeSphereIsAClosedUnitSphere) {
  const ps::MeshData s = ps::cube_sphere(6);
  EXPECT_EQ(s.triangle_count(), 12u * 36u);
  EXPECT_TRUE(ps::test::is_closed_and_oriented(triangles_of(s)));
  for (const glm::vec3& p : s.positions) EXPECT_NEAR(glm::length(p), 1.0f, 1e-6f);
  expect_facing(s, glm::vec3(0.0f), Facing::outward, 0.95f);
}

TEST(Geometry, OrientedQuadLooksTowardsOrAwayFromAPoint) {
  const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(1, 1, 0), d(0, 1, 0);
  for (glm::vec3 reference : {glm::vec3(0.5f, 0.5f, 1.0f), glm::vec3(0.5f, 0.5f, -1.0f)}) {
    const ps::MeshData in = ps::oriented_quad(a, b, c, d, reference, Facing::inward);
    const ps::MeshData out = ps::oriented_quad(a, b, c, d, reference, Facing::outward);
    EXPECT_GT(glm::dot(triangles_of(in)[0].normal(), reference - glm::vec3(0.5f, 0.5f, 0)), 0.0f);
    EXPECT_LT(glm::dot(triangles_of(out)[0].normal(), reference - glm::vec3(0.5f, 0.5f, 0)), 0.0f);
  }
}

TEST(Geometry, MirroringKeepsFrontFacesOutside) {
  const glm::mat4 mirror = glm::scale(glm::mat4(1.0f), glm::vec3(-2.0f, 1.0f, 1.0f));
  const ps::MeshData b = ps::transformed(ps::box({0, 0, 0}, {1, 1, 1}, Facing::outward), mirror);
  expect_facing(b, {-1.0f, 0.5f, 0.5f}, Facing::outward);
  EXPECT_TRUE(ps::test::is_closed_and_oriented(triangles_of(b)));
}

TEST(Geometry, FlippedTurnsABoxInsideOut) {
  const ps::MeshData b = ps::flipped(ps::box({0, 0, 0}, {1, 1, 1}, Facing::outward));
  expect_facing(b, glm::vec3(0.5f), Facing::inward);
}

TEST(Geometry, AppendReindexes) {
  ps::MeshData m = ps::quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  m.append(ps::quad({0, 0, 1}, {1, 0, 0}, {0, 1, 0}));
  EXPECT_EQ(m.triangle_count(), 4u);
  EXPECT_EQ(m.indices[6], 4u);
}
