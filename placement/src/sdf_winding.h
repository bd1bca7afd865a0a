// The winding side of the scene's signed distance field (scene_sdf.cpp): angle-weighted pseudonormals
// (Bærentzen & Aanæs 2005) over a vertex-welded copy of a triangle set, which decide on which side of its
// closest triangle an enclosed voxel lies. Plain geometry: no OpenVDB here.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace probebake::placement {

// ---- winding: angle-weighted pseudonormals over a vertex-welded copy of the mesh ----

enum class Feature { face, vertex0, vertex1, vertex2, edge01, edge12, edge20 };

// The triangles of one kind (single- or double-sided) over the scene's positions; closest-triangle
// indices of the field built from it index `triangles`.
struct TriangleSet {
  const std::vector<glm::vec3>* positions = nullptr;
  std::vector<glm::uvec3> triangles;
  bool empty() const { return triangles.empty(); }
};

class Pseudonormals {
public:
  explicit Pseudonormals(const TriangleSet& set);

  // > 0: x is on the front (free) side of its closest triangle, < 0: behind it, 0: undecidable
  // (degenerate triangle, x on the surface).
  double side(std::size_t triangle, glm::dvec3 x) const;

private:
  static std::uint64_t edge_key(std::uint32_t a, std::uint32_t b);

  void weld(const TriangleSet& set);
  void accumulate();
  glm::dvec3 normal_of(std::size_t triangle, Feature feature) const;

  std::vector<glm::dvec3> pos_;
  std::vector<std::array<std::uint32_t, 3>> tris_;
  std::vector<glm::dvec3> face_normal_;
  std::vector<glm::dvec3> vertex_normal_;
  std::vector<glm::dvec3> edge_normal_; // one per welded edge
  std::vector<std::uint32_t> edge_of_;  // 3 * triangle + k: the edge from vertex k to k + 1 (mod 3)
};

} // namespace probebake::placement
