// Ray queries against a loaded scene with Embree 3 (CPU). Built once, then safe to query from many
// threads at once. Distances are in scene units; directions need not be normalised for occlusion.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include <glm/vec3.hpp>

#include "probebake/scene/scene.h"

namespace probebake::scene {

struct RayHit {
  float distance = 0.0f;      // along the (normalised) ray direction
  std::uint32_t triangle = 0; // index into Scene::triangles
  glm::vec3 normal{0.0f};     // unit geometric normal of the triangle's front side (CCW)
  bool backface = false;      // the ray arrived at the triangle's back side
  bool double_sided = false;  // the triangle's material is glTF doubleSided: both sides reflect and emit
  float u = 0.0f, v = 0.0f;   // barycentrics of the hit (weights of vertices 1 and 2)

  // The ray is inside a solid: it arrived at the back of a single-sided surface (black, absorbing,
  // non-emitting). The back of a double-sided surface is open space like its front.
  bool inside() const { return backface && !double_sided; }
  // The unit normal of the side the ray arrived at (the side that reflects and emits towards it); only
  // meaningful when !inside().
  glm::vec3 facing_normal() const { return backface ? -normal : normal; }
};

class RayScene {
public:
  // Builds a BVH over every triangle of `scene` (static and dynamic). `scene` must outlive the RayScene.
  explicit RayScene(const Scene& scene);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;
  RayScene(RayScene&&) noexcept;
  RayScene& operator=(RayScene&&) noexcept;

  // Closest hit along origin + t * direction for t in [t_min, t_max]; direction must be unit length.
  std::optional<RayHit> intersect(const glm::vec3& origin, const glm::vec3& direction, float t_min = 0.0f,
                                  float t_max = 3.0e38f) const;
  // True when anything blocks the segment origin + t * direction, t in [t_min, t_max].
  bool occluded(const glm::vec3& origin, const glm::vec3& direction, float t_min, float t_max) const;

  const Scene& scene() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace probebake::scene
