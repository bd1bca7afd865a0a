// Signed distance field of a scene, used to move "dead" probes (probes inside geometry) out to a minimum
// clearance from every surface: the field's gradient is a geometry-aware direction to push a probe along.
//
// Sign convention (negative = inside solid, positive = free space):
//  - Closed solids whose normals point out (a cube, a thick wall) are negative inside.
//  - Closed shells whose normals point in (a room, a box seen from inside) are positive inside: their
//    interior is free space. Winding decides, so a solid standing in a closed room is still negative.
//  - Open meshes (a single wall, a plane, a room with a missing wall) have no inside: where such a surface
//    is reachable from outside the scene's bounds the field is the unsigned distance, positive on both
//    sides. Inside a closed region, the back side of a one-sided surface counts as solid up to the points
//    nearer to another surface (as the backface test of the DDGI relocation paper, §3.1, does).
//  - glTF doubleSided triangles (Scene::materials) are thin shells: never inside on either side, the
//    unsigned distance to them counts (a room of reversed double-sided walls is free space inside; a
//    double-sided plane inside a single-sided solid leaves the solid negative). Scenes built without
//    materials are single-sided.
//
// Values: distances in world units, exact inside closed regions (solids and rooms are filled to their
// deepest point, so a probe deep inside a wall still has a gradient), and saturating at +band_width()
// in free space farther than the narrow band from every surface (also far outside the scene's bounds).
//
// Thread-safety: every const method may be called from any number of threads at once. Deterministic:
// the same scene and settings give the same values bit for bit, whatever the thread count.
#pragma once

#include "probebake/scene/scene.h"

#include <glm/vec3.hpp>

#include <memory>
#include <optional>

namespace probebake::placement {

struct SdfSettings {
  // World units; 0 = automatic: the scene's bounding-box diagonal / 256, made coarser if the grid's
  // bounding box would hold more than ~16M voxels. An explicit size is used as given.
  float voxel_size = 0;
  // Narrow-band half-width in voxels: positive distances saturate at band_voxels * voxel_size, so it
  // must cover the largest clearance asked of push_out (at least 1).
  float band_voxels = 3;
};

class SceneSdf {
public:
  // Builds the field from the scene's triangles. A scene without triangles gives an empty field
  // (+band_width() everywhere). Throws std::invalid_argument for non-finite positions or settings.
  explicit SceneSdf(const scene::Scene& scene, const SdfSettings& settings = {});
  ~SceneSdf();
  // Move-only; a moved-from SceneSdf may only be destroyed or assigned to.
  SceneSdf(SceneSdf&&) noexcept;
  SceneSdf& operator=(SceneSdf&&) noexcept;
  SceneSdf(const SceneSdf&) = delete;
  SceneSdf& operator=(const SceneSdf&) = delete;

  float voxel_size() const;
  // Positive distances are clamped to this (band_voxels * voxel_size).
  float band_width() const;
  // Trilinear sample in world units, <= band_width(). Never NaN for finite p (a non-finite p reads
  // +band_width()).
  float distance(glm::vec3 p) const;
  // Unit gradient of distance() by central differences one voxel wide; (0,0,0) where the field is flat
  // (saturated free space, empty field) or p is not finite.
  glm::vec3 gradient(glm::vec3 p) const;
  // Moves p along the gradient until distance(p) >= clearance: steps of at most one voxel, or the exact
  // remaining distance when that is smaller, at most max_steps of them. Returns p itself when it already
  // has the clearance, nullopt when it did not get there: max_steps too small, a local maximum of the
  // field below the clearance (e.g. a gap narrower than twice the clearance), or
  // clearance > band_width(), which the saturated field cannot confirm. On a flat spot (the centre of a symmetric solid) it leaves along
  // the axis direction that gains most, +x first on ties.
  std::optional<glm::vec3> push_out(glm::vec3 p, float clearance, int max_steps = 64) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace probebake::placement
