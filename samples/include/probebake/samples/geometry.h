// Triangle meshes for procedural test scenes: quads, boxes facing in or out, cube spheres.
//
// Conventions: metres, Y up, counter-clockwise triangles are front faces, normals point out of the front
// face. Plain value types; functions are pure and thread-safe.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace probebake::samples {

// An indexed triangle list with one normal per vertex.
struct MeshData {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;     // same size as positions, unit length
  std::vector<std::uint32_t> indices; // 3 per triangle, counter-clockwise = front

  std::size_t triangle_count() const { return indices.size() / 3; }
  bool empty() const { return indices.empty(); }
  // Appends other's triangles (re-indexed) to this mesh.
  void append(const MeshData& other);
};

// Axis-aligned bounds; empty (min > max) until a point is added.
struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};

  bool empty() const { return min.x > max.x; }
  void extend(glm::vec3 p);
  void extend(const Bounds& other);
  glm::vec3 extent() const { return empty() ? glm::vec3(0.0f) : max - min; }
  glm::vec3 centre() const { return (min + max) * 0.5f; }
};

enum class Facing { outward, inward };

// A parallelogram corner + s*edge_u + t*edge_v (s, t in [0, 1]) split into subdivisions^2 cells, two
// triangles each. The front face (and normal) is along cross(edge_u, edge_v). subdivisions >= 1.
MeshData quad(glm::vec3 corner, glm::vec3 edge_u, glm::vec3 edge_v, int subdivisions = 1);

// The quad a-b-c-d (possibly slightly non-planar, like measured data) as two triangles a-b-c, a-c-d. Its
// winding is chosen so the front faces look towards `toward` (Facing::inward) or away from it
// (Facing::outward); one flat normal from the diagonals' cross product.
MeshData oriented_quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 toward, Facing facing);

// The six faces of [min, max], each split into subdivisions^2 cells: 12 * subdivisions^2 triangles.
// Outward: front faces outside (a solid); inward: front faces inside (a room). Vertices on shared edges
// have bit-identical positions, so the box is closed when welded by position.
MeshData box(glm::vec3 min, glm::vec3 max, Facing facing, int subdivisions = 1);

// A unit-radius sphere centred at the origin made by projecting a subdivided cube: 12 * subdivisions^2
// triangles, front faces outside, closed like box().
MeshData cube_sphere(int subdivisions);

// The mesh with every position transformed by m (normals by its inverse transpose); the winding is
// reversed when m mirrors, so front faces stay front faces.
MeshData transformed(const MeshData& mesh, const glm::mat4& m);

// The mesh seen from the other side: reversed winding and negated normals.
MeshData flipped(const MeshData& mesh);

Bounds bounds_of(const MeshData& mesh);

} // namespace probebake::samples
