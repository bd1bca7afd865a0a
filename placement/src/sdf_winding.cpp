// Angle-weighted pseudonormals for the scene SDF's re-signing (sdf_winding.h): the closest point on a
// triangle with the Voronoi region it lands in, the welded mesh and its face, edge and vertex normals.
#include "sdf_winding.h"

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

namespace probebake::placement {
namespace {

struct ClosestPoint {
  glm::dvec3 point;
  Feature feature;
};

// Ericson, Real-Time Collision Detection §5.1.5, with the Voronoi region it lands in.
ClosestPoint closest_on_triangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {a, Feature::vertex0};
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {b, Feature::vertex1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {a + ab * (d1 / (d1 - d3)), Feature::edge01};
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {c, Feature::vertex2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {a + ac * (d2 / (d2 - d6)), Feature::edge20};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return {b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))), Feature::edge12};
  const double denom = 1.0 / (va + vb + vc);
  return {a + ab * (vb * denom) + ac * (vc * denom), Feature::face};
}

} // namespace

Pseudonormals::Pseudonormals(const TriangleSet& set) {
  weld(set);
  accumulate();
}

double Pseudonormals::side(std::size_t triangle, glm::dvec3 x) const {
  if (face_normal_[triangle] == glm::dvec3(0.0)) return 0.0;
  const std::array<std::uint32_t, 3>& t = tris_[triangle];
  const ClosestPoint cp = closest_on_triangle(x, pos_[t[0]], pos_[t[1]], pos_[t[2]]);
  return glm::dot(x - cp.point, normal_of(triangle, cp.feature));
}

std::uint64_t Pseudonormals::edge_key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

// glTF splits vertices at UV and normal seams; pseudonormals need shared edges, so weld by position
// (bit pattern). Sorted, not hashed: (key, index) orders are total, so the ids are the same on every run.
void Pseudonormals::weld(const TriangleSet& set) {
  using Key = std::array<std::uint32_t, 3>;
  const std::vector<glm::vec3>& positions = *set.positions;
  std::vector<std::pair<Key, std::uint32_t>> keyed(positions.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, positions.size()), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const glm::vec3 p = positions[i] + glm::vec3(0.0f); // -0 -> +0
      std::memcpy(keyed[i].first.data(), &p, sizeof(Key));
      keyed[i].second = std::uint32_t(i);
    }
  });
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> remap(positions.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first)
      pos_.push_back(glm::dvec3(positions[keyed[i].second] + glm::vec3(0.0f)));
    remap[keyed[i].second] = std::uint32_t(pos_.size() - 1);
  }
  tris_.reserve(set.triangles.size());
  for (const glm::uvec3& t : set.triangles) tris_.push_back({remap[t.x], remap[t.y], remap[t.z]});
}

// Sums in triangle order (edges: sorted by key, then by triangle), so the field is the same on every run.
void Pseudonormals::accumulate() {
  vertex_normal_.assign(pos_.size(), glm::dvec3(0.0));
  face_normal_.reserve(tris_.size());
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges; // (edge key, 3 * triangle + k)
  edges.reserve(3 * tris_.size());
  for (const std::array<std::uint32_t, 3>& t : tris_) {
    const glm::dvec3 cross = glm::cross(pos_[t[1]] - pos_[t[0]], pos_[t[2]] - pos_[t[0]]);
    const double area2 = glm::length(cross);
    const glm::dvec3 n = area2 > 0.0 ? cross / area2 : glm::dvec3(0.0);
    face_normal_.push_back(n);
    if (area2 == 0.0) continue;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 e1 = glm::normalize(pos_[t[(k + 1) % 3]] - pos_[t[k]]);
      const glm::dvec3 e2 = glm::normalize(pos_[t[(k + 2) % 3]] - pos_[t[k]]);
      vertex_normal_[t[k]] += std::acos(std::clamp(glm::dot(e1, e2), -1.0, 1.0)) * n;
      edges.emplace_back(edge_key(t[k], t[(k + 1) % 3]), std::uint32_t(3 * (face_normal_.size() - 1) + std::size_t(k)));
    }
  }
  tbb::parallel_sort(edges.begin(), edges.end());
  edge_of_.assign(3 * tris_.size(), 0);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (i == 0 || edges[i].first != edges[i - 1].first) edge_normal_.push_back(glm::dvec3(0.0));
    edge_normal_.back() += face_normal_[edges[i].second / 3];
    edge_of_[edges[i].second] = std::uint32_t(edge_normal_.size() - 1);
  }
}

glm::dvec3 Pseudonormals::normal_of(std::size_t triangle, Feature feature) const {
  const std::array<std::uint32_t, 3>& t = tris_[triangle];
  switch (feature) {
  case Feature::vertex0: return vertex_normal_[t[0]];
  case Feature::vertex1: return vertex_normal_[t[1]];
  case Feature::vertex2: return vertex_normal_[t[2]];
  case Feature::edge01: return edge_normal_[edge_of_[3 * triangle]];
  case Feature::edge12: return edge_normal_[edge_of_[3 * triangle + 1]];
  case Feature::edge20: return edge_normal_[edge_of_[3 * triangle + 2]];
  case Feature::face: break;
  }
  return face_normal_[triangle];
}

} // namespace probebake::placement
