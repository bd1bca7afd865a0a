// Procedural triangle meshes (see geometry.h for conventions).
#include "probebake/samples/geometry.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <utility>

namespace probebake::samples {
namespace {

std::uint32_t vertex_count(const MeshData& mesh) { return static_cast<std::uint32_t>(mesh.positions.size()); }

void add_triangle(MeshData& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  mesh.indices.insert(mesh.indices.end(), {a, b, c});
}

// Two counter-clockwise triangles per cell of a (cells+1) x (cells+1) vertex grid starting at `first`,
// row-major in (u, v): the front face is along cross(u, v).
void add_grid_triangles(MeshData& mesh, std::uint32_t first, int cells) {
  const auto row = static_cast<std::uint32_t>(cells + 1);
  for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(cells); ++j) {
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(cells); ++i) {
      const std::uint32_t v00 = first + j * row + i;
      add_triangle(mesh, v00, v00 + 1, v00 + row + 1);
      add_triangle(mesh, v00, v00 + row + 1, v00 + row);
    }
  }
}

void reverse_winding(MeshData& mesh) {
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
}

// Coordinate i of `cells` steps from lo to hi, exact at both ends so that faces sharing an edge compute
// bit-identical positions.
float grid_coordinate(float lo, float hi, int i, int cells) {
  if (i == cells) return hi;
  return lo + (hi - lo) * (static_cast<float>(i) / static_cast<float>(cells));
}

// One face of a box: the face with normal +/- axis `normal_axis`, front face outside the box.
MeshData box_face(glm::vec3 lo, glm::vec3 hi, int normal_axis, bool positive, int cells) {
  const int a = (normal_axis + 1) % 3; // e_a x e_b = e_normal for cyclic axes
  const int b = (normal_axis + 2) % 3;
  glm::vec3 normal(0.0f);
  normal[normal_axis] = positive ? 1.0f : -1.0f;
  MeshData face;
  for (int j = 0; j <= cells; ++j) {
    for (int i = 0; i <= cells; ++i) {
      glm::vec3 p;
      p[normal_axis] = positive ? hi[normal_axis] : lo[normal_axis];
      p[a] = grid_coordinate(lo[a], hi[a], i, cells);
      p[b] = grid_coordinate(lo[b], hi[b], j, cells);
      face.positions.push_back(p);
      face.normals.push_back(normal);
    }
  }
  add_grid_triangles(face, 0, cells);
  if (!positive) reverse_winding(face);
  return face;
}

} // namespace

void MeshData::append(const MeshData& other) {
  const std::uint32_t base = vertex_count(*this);
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  for (std::uint32_t index : other.indices) indices.push_back(base + index);
}

void Bounds::extend(glm::vec3 p) {
  min = glm::min(min, p);
  max = glm::max(max, p);
}

void Bounds::extend(const Bounds& other) {
  if (other.empty()) return;
  extend(other.min);
  extend(other.max);
}

MeshData quad(glm::vec3 corner, glm::vec3 edge_u, glm::vec3 edge_v, int subdivisions) {
  const int cells = subdivisions < 1 ? 1 : subdivisions;
  const glm::vec3 normal = glm::normalize(glm::cross(edge_u, edge_v));
  MeshData mesh;
  for (int j = 0; j <= cells; ++j) {
    for (int i = 0; i <= cells; ++i) {
      const float s = static_cast<float>(i) / static_cast<float>(cells);
      const float t = static_cast<float>(j) / static_cast<float>(cells);
      mesh.positions.push_back(corner + s * edge_u + t * edge_v);
      mesh.normals.push_back(normal);
    }
  }
  add_grid_triangles(mesh, 0, cells);
  return mesh;
}

MeshData oriented_quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 toward, Facing facing) {
  glm::vec3 normal = glm::normalize(glm::cross(c - a, d - b));
  const glm::vec3 centroid = (a + b + c + d) * 0.25f;
  const bool faces_toward = glm::dot(normal, toward - centroid) > 0.0f;
  if (faces_toward != (facing == Facing::inward)) {
    std::swap(b, d);
    normal = -normal;
  }
  MeshData mesh;
  mesh.positions = {a, b, c, d};
  mesh.normals.assign(4, normal);
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

MeshData box(glm::vec3 min, glm::vec3 max, Facing facing, int subdivisions) {
  const int cells = subdivisions < 1 ? 1 : subdivisions;
  MeshData mesh;
  for (int axis = 0; axis < 3; ++axis) {
    mesh.append(box_face(min, max, axis, false, cells));
    mesh.append(box_face(min, max, axis, true, cells));
  }
  return facing == Facing::inward ? flipped(mesh) : mesh;
}

MeshData cube_sphere(int subdivisions) {
  MeshData mesh = box(glm::vec3(-1.0f), glm::vec3(1.0f), Facing::outward, subdivisions);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    mesh.positions[v] = glm::normalize(mesh.positions[v]);
    mesh.normals[v] = mesh.positions[v];
  }
  return mesh;
}

MeshData transformed(const MeshData& mesh, const glm::mat4& m) {
  MeshData out = mesh;
  const glm::mat3 linear(m);
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
  for (std::size_t v = 0; v < out.positions.size(); ++v) {
    out.positions[v] = glm::vec3(m * glm::vec4(mesh.positions[v], 1.0f));
    out.normals[v] = glm::normalize(normal_matrix * mesh.normals[v]);
  }
  if (glm::determinant(linear) < 0.0f) reverse_winding(out);
  return out;
}

MeshData flipped(const MeshData& mesh) {
  MeshData out = mesh;
  for (glm::vec3& n : out.normals) n = -n;
  reverse_winding(out);
  return out;
}

Bounds bounds_of(const MeshData& mesh) {
  Bounds bounds;
  for (const glm::vec3& p : mesh.positions) bounds.extend(p);
  return bounds;
}

} // namespace probebake::samples
