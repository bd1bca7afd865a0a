// Scene signed distance field for dead-probe relocation.
//
// Roháček & Iser, "Improving Probes in Dynamic Diffuse Global Illumination" (CESCG 2022),
// /work/shared/papers/ddgi-probe-relocation.txt: §3.1 marks a probe "dead" when most of its rays hit
// backfaces within a clearance; §3.2 moves it along a geometry-unaware spiral and leaves a
// geometry-aware move as future work. This field is that geometry-aware move: the SDF gradient points
// away from the nearest surface, and push_out() walks along it to the clearance the paper asks for.
//
// Construction: OpenVDB's meshToVolume (the general form of meshToSignedDistanceField; meshToLevelSet is
// its symmetric narrow-band case) with
//  - an exterior band of band_voxels: free space only needs distances up to the largest clearance;
//  - an interior band as deep as any enclosed point can be (half the smallest extent of the bounds), so
//    a probe deep inside a solid still sees a gradient. A symmetric narrow band (meshToLevelSet) would
//    leave the inside flat at -band, where push_out has no direction to go;
//  - the closest-triangle index grid, used below to fix the sign;
//  - surfaces inside other closed surfaces kept (OpenVDB would remove them as self-intersections).
// OpenVDB decides inside/outside by flood-filling from outside the mesh, ignoring winding: any closed
// surface, a room included, encloses "inside". So every enclosed voxel is then re-signed from the winding
// of its closest triangle, with the angle-weighted pseudonormal of the closest feature (face, edge or
// vertex; Bærentzen & Aanæs 2005; sdf_winding.cpp), which gives the right sign for closed oriented meshes
// also near edges and corners. Voxels reachable from outside stay positive: open meshes have no inside.
//
// glTF doubleSided triangles are thin shells: both sides are open space, so they may never make anything
// "inside", yet probes keep their clearance from them. They are left out of the signed field above (a
// room modelled as double-sided planes would otherwise enclose an "inside" wherever winding says so) and
// get a second, unsigned narrow-band field (meshToVolume with UNSIGNED_DISTANCE_FIELD). distance() is
// the minimum of the two: the distance to the union of both surface sets, negative only inside a solid
// of single-sided geometry (a double-sided decal inside a wall stays inside the wall).
#include "probebake/placement/scene_sdf.h"

#include "sdf_winding.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace probebake::placement {
namespace {

using FloatGrid = openvdb::FloatGrid;
using IndexGrid = openvdb::Int32Grid;

constexpr float auto_voxel_divisions = 256.0f; // voxels along the bounding-box diagonal
constexpr double max_auto_voxels = 16.0 * 1024 * 1024;
constexpr float flat_gradient = 1e-3f; // |grad| below this (per unit length) counts as flat

void initialize_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

template <typename Vec>
bool all_finite(const Vec& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Bounds of the vertices the triangles use (scene.bounds may be unset in scenes built by hand).
scene::Bounds triangle_bounds(const scene::Scene& scene) {
  scene::Bounds bounds;
  for (const glm::uvec3& t : scene.triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] >= scene.positions.size())
        throw std::invalid_argument("SceneSdf: triangle index " + std::to_string(t[k]) + " out of range");
      const glm::vec3& p = scene.positions[t[k]];
      if (!all_finite(p)) throw std::invalid_argument("SceneSdf: vertex position is not finite");
      bounds.extend(p);
    }
  }
  return bounds;
}

void validate(const SdfSettings& s) {
  if (!std::isfinite(s.voxel_size) || s.voxel_size < 0.0f)
    throw std::invalid_argument("SceneSdf: voxel_size must be finite and >= 0");
  if (!std::isfinite(s.band_voxels) || s.band_voxels < 1.0f)
    throw std::invalid_argument("SceneSdf: band_voxels must be finite and >= 1");
}

// Diagonal / 256, coarsened so that the bounds padded by the band hold at most ~16M voxels (a filled
// interior can make every one of them active). 256 divisions alone give at most ~3.3M voxels (a cube),
// so this binds only with wide bands.
float auto_voxel_size(const scene::Bounds& bounds, float band_voxels) {
  const glm::vec3 extent = bounds.max - bounds.min;
  const float voxel = glm::length(extent) / auto_voxel_divisions;
  const glm::dvec3 padded = glm::dvec3(extent) + 2.0 * double(band_voxels + 1.0f) * double(voxel);
  const double budget_voxel = std::cbrt(padded.x * padded.y * padded.z / max_auto_voxels);
  return std::max(voxel, float(budget_voxel));
}

// Deep enough that every enclosed voxel gets a distance: from inside a closed region, a ray along
// each axis hits the surface both ways, so no enclosed point is deeper than half the smallest extent.
float interior_band_voxels(const scene::Bounds& bounds, float voxel, float band_voxels) {
  const glm::vec3 extent = bounds.max - bounds.min;
  const float smallest = std::min({extent.x, extent.y, extent.z});
  return std::max(band_voxels, std::ceil(0.5f * smallest / voxel) + 2.0f);
}

// ---- the triangle sets: single- and double-sided (the winding of one: sdf_winding.h) ----

// Hand-built scenes (tests) may have no materials: their triangles are single-sided.
bool double_sided(const scene::Scene& scene, std::size_t t) {
  return t < scene.triangle_material.size() && scene.triangle_material[t] < scene.materials.size() &&
         scene::is_double_sided(scene, t);
}

std::pair<TriangleSet, TriangleSet> split_by_sides(const scene::Scene& scene) {
  TriangleSet single{&scene.positions, {}}, both{&scene.positions, {}};
  for (std::size_t t = 0; t < scene.triangles.size(); ++t)
    (double_sided(scene, t) ? both : single).triangles.push_back(scene.triangles[t]);
  return {std::move(single), std::move(both)};
}

scene::Bounds set_bounds(const TriangleSet& set) {
  scene::Bounds bounds;
  for (const glm::uvec3& t : set.triangles)
    for (int k = 0; k < 3; ++k) bounds.extend((*set.positions)[t[k]]);
  return bounds;
}

// ---- building ----

// `flags`: extra meshToVolume flags (UNSIGNED_DISTANCE_FIELD for the double-sided shells).
FloatGrid::Ptr mesh_to_volume(const TriangleSet& set, float voxel, float exterior, float interior, IndexGrid& closest,
                              int flags = 0) {
  std::vector<openvdb::Vec3s> points;
  points.reserve(set.positions->size());
  for (const glm::vec3& p : *set.positions) points.emplace_back(p.x / voxel, p.y / voxel, p.z / voxel);
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(set.triangles.size());
  for (const glm::uvec3& t : set.triangles) triangles.emplace_back(t.x, t.y, t.z);

  const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> mesh(points, triangles);
  // Index space throughout (distances in voxels, scaled by Impl::sample): OpenVDB refuses a transform
  // whose determinant voxel^3 is below its tolerance (about 1e-8), i.e. every scene under ~0.5 m across.
  const openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(1.0);
  // OpenVDB would delete surfaces lying inside another closed surface (it takes them for self-intersection
  // debris) and renormalise the distances around them: a solid standing in a closed room would vanish.
  // Keep every surface and the exact closest-triangle distances; resign_enclosed sorts out the sign.
  flags |= openvdb::tools::DISABLE_INTERSECTING_VOXEL_REMOVAL | openvdb::tools::DISABLE_RENORMALIZATION;
  return openvdb::tools::meshToVolume<FloatGrid>(mesh, *transform, exterior, interior, flags, &closest);
}

// Enclosed voxels (negative after OpenVDB's flood fill) on the front side of their closest triangle
// are free space (the inside of a room): flip them. Per voxel and independent, so parallel and
// deterministic.
void resign_enclosed(FloatGrid& grid, const IndexGrid& closest, const Pseudonormals& normals, float voxel) {
  std::vector<FloatGrid::TreeType::LeafNodeType*> leaves;
  grid.tree().getNodes(leaves);
  const IndexGrid::TreeType& index_tree = closest.tree();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      FloatGrid::TreeType::LeafNodeType& leaf = *leaves[i];
      const IndexGrid::TreeType::LeafNodeType* index_leaf = index_tree.probeConstLeaf(leaf.origin());
      if (!index_leaf) continue;
      for (openvdb::Index n = 0; n < leaf.SIZE; ++n) {
        const float value = leaf.getValue(n);
        const openvdb::Int32 triangle = index_leaf->getValue(n);
        if (!(value < 0.0f) || triangle < 0) continue;
        const openvdb::Coord ijk = leaf.offsetToGlobalCoord(n);
        const glm::dvec3 x = glm::dvec3(ijk.x(), ijk.y(), ijk.z()) * double(voxel);
        if (normals.side(std::size_t(triangle), x) > 0.0) leaf.setValueOnly(n, -value);
      }
    }
  });
}

} // namespace

struct SceneSdf::Impl {
  float voxel = 1.0f;
  float band = 1.0f;
  FloatGrid::Ptr grid;   // signed, single-sided triangles; null when there are none
  FloatGrid::Ptr shells; // unsigned, double-sided triangles; null when there are none

  // Trilinear sample of one grid in world units, +band where it is absent or p is not finite.
  float sample_grid(const FloatGrid::Ptr& g, glm::vec3 p) const {
    if (!g || !all_finite(p)) return band;
    const FloatGrid::ConstUnsafeAccessor accessor = g->getConstUnsafeAccessor(); // per call: thread-safe
    const openvdb::Vec3R index(double(p.x) / voxel, double(p.y) / voxel, double(p.z) / voxel);
    const float d = openvdb::tools::BoxSampler::sample(accessor, index) * voxel; // voxels to metres
    return std::isnan(d) ? band : std::min(d, band);
  }

  // Distance to the union of solids and shells (see the construction note at the top).
  float sample(glm::vec3 p) const { return std::min(sample_grid(grid, p), sample_grid(shells, p)); }

  // Steepest one-sided ascent along the six axes (first in +x,-x,+y,-y,+z,-z order on ties): the way
  // out where central differences cancel, e.g. at the centre of a symmetric solid.
  glm::vec3 axis_escape(glm::vec3 p, float d) const {
    glm::vec3 best(0.0f);
    float best_gain = flat_gradient * voxel;
    for (int axis = 0; axis < 3; ++axis) {
      for (float sign : {1.0f, -1.0f}) {
        glm::vec3 dir(0.0f);
        dir[axis] = sign;
        const float gain = sample(p + dir * voxel) - d;
        if (gain > best_gain) {
          best_gain = gain;
          best = dir;
        }
      }
    }
    return best;
  }
};

SceneSdf::SceneSdf(const scene::Scene& scene, const SdfSettings& settings) : impl_(std::make_unique<Impl>()) {
  validate(settings);
  const scene::Bounds bounds = triangle_bounds(scene);
  const float auto_voxel = bounds.empty() ? 0.0f : auto_voxel_size(bounds, settings.band_voxels);
  const float voxel = settings.voxel_size > 0.0f ? settings.voxel_size : auto_voxel;
  impl_->voxel = voxel > 0.0f ? voxel : 1.0f; // empty or point-like scene: nothing to resolve
  impl_->band = settings.band_voxels * impl_->voxel;
  if (bounds.empty() || !(voxel > 0.0f)) return;

  initialize_openvdb();
  const auto [single, both] = split_by_sides(scene);
  if (!single.empty()) {
    IndexGrid closest(static_cast<openvdb::Int32>(openvdb::util::INVALID_IDX));
    const float interior = interior_band_voxels(set_bounds(single), voxel, settings.band_voxels);
    impl_->grid = mesh_to_volume(single, voxel, settings.band_voxels, interior, closest);
    resign_enclosed(*impl_->grid, closest, Pseudonormals(single), voxel);
  }
  if (!both.empty()) {
    IndexGrid closest(static_cast<openvdb::Int32>(openvdb::util::INVALID_IDX));
    impl_->shells =
        mesh_to_volume(both, voxel, settings.band_voxels, 0.0f, closest, openvdb::tools::UNSIGNED_DISTANCE_FIELD);
  }
}

SceneSdf::~SceneSdf() = default;
SceneSdf::SceneSdf(SceneSdf&&) noexcept = default;
SceneSdf& SceneSdf::operator=(SceneSdf&&) noexcept = default;

float SceneSdf::voxel_size() const { return impl_->voxel; }
float SceneSdf::band_width() const { return impl_->band; }
float SceneSdf::distance(glm::vec3 p) const { return impl_->sample(p); }

glm::vec3 SceneSdf::gradient(glm::vec3 p) const {
  if (!all_finite(p)) return glm::vec3(0.0f);
  const float h = impl_->voxel;
  glm::vec3 g;
  for (int axis = 0; axis < 3; ++axis) {
    glm::vec3 step(0.0f);
    step[axis] = h;
    g[axis] = (impl_->sample(p + step) - impl_->sample(p - step)) / (2.0f * h);
  }
  const float length = glm::length(g);
  return length > flat_gradient ? g / length : glm::vec3(0.0f);
}

std::optional<glm::vec3> SceneSdf::push_out(glm::vec3 p, float clearance, int max_steps) const {
  if (!all_finite(p) || !(clearance <= impl_->band)) return std::nullopt;
  // No early exit on a ridge (steps that gain nothing): walks that zig-zag across one often drift along
  // it to an opening, and max_steps bounds the cost of those that do not.
  for (int step = 0;; ++step) {
    const float d = impl_->sample(p);
    if (d >= clearance) return p;
    if (step >= max_steps) return std::nullopt;
    glm::vec3 dir = gradient(p);
    if (dir == glm::vec3(0.0f)) dir = impl_->axis_escape(p, d);
    if (dir == glm::vec3(0.0f)) return std::nullopt;
    // |grad| = 1 in a distance field, so the remaining gap is the step; a hair more so that trilinear
    // error does not leave it a few ulps short forever.
    p += dir * std::min(impl_->voxel, clearance - d + 1e-3f * impl_->voxel);
  }
}

} // namespace probebake::placement
