// Octree probe placement (octree-probe-surfel-placement-ddgi-thesis §3.2.2, state L1 and the M1-M3
// transitions it triggers), evaluated breadth-first on the CPU until the tree no longer changes.
//
// One addition to the thesis's rule: a node whose centre probe sees too little (f < LOW) but whose cube
// still overlaps triangles is split rather than left empty while it is above max depth. The thesis's
// scenes fill the root cube; in a scene that does not (two rooms in a wide root cube, a room below a
// tall one) the first children's centres lie outside the rooms, see only the backs of floors and
// ceilings, and the rule alone would free every probe before the tree reached the rooms. A centre that
// mostly sees back faces of single-sided surfaces (it is inside geometry) is treated the same way; the
// back of a double-sided surface is open space and counts as an ordinary hit. So is a centre lying on a
// double-sided surface (nearer than the clearance): with no back to tell its sides apart, half its rays
// end at once whatever the node holds; without this, closed rooms of double-sided walls (open space
// outside them too) stopped refining at depth 2 with their probes on the walls.
#include "placement.h"

#include <algorithm>
#include <array>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "parallel.h"
#include "probebake/bake/lattice.h"

namespace probebake::bake::detail {
namespace {

// Triangles whose bounding boxes overlap a node's cube, handed down from parent to children.
using TriangleList = std::vector<std::uint32_t>;

bool box_overlaps_cube(const scene::Scene& s, std::uint32_t t, const formats::NodeCube& c) {
  const glm::uvec3 tri = s.triangles[t];
  const glm::vec3 lo = glm::min(glm::min(s.positions[tri.x], s.positions[tri.y]), s.positions[tri.z]);
  const glm::vec3 hi = glm::max(glm::max(s.positions[tri.x], s.positions[tri.y]), s.positions[tri.z]);
  const glm::vec3 cmax = c.min + glm::vec3(c.size);
  return glm::all(glm::lessThanEqual(lo, cmax)) && glm::all(glm::greaterThanEqual(hi, c.min));
}

TriangleList overlapping(const scene::Scene& s, const TriangleList& parent, const formats::NodeCube& cube) {
  TriangleList out;
  for (std::uint32_t t : parent)
    if (box_overlaps_cube(s, t, cube)) out.push_back(t);
  return out;
}

Cube to_cube(const formats::NodeCube& c) { return {c.min, c.size}; }

std::vector<ProbeRays> trace_all(const PlacementInput& in, const std::vector<Cube>& cubes,
                                 const std::vector<glm::vec3>& positions) {
  std::vector<ProbeRays> results(cubes.size());
  parallel_for(cubes.size(), in.settings->threads,
               [&](std::size_t i) { results[i] = trace_probe(*in.rays, positions[i], cubes[i], in.directions); });
  return results;
}

constexpr int kSealRays = 64; // per sample point, over the front hemisphere
constexpr int kSealScreenStride = 8; // 8 of the 64 directions screen first

// Fibonacci directions flipped into the hemisphere around `n` (the sphere lattice is symmetric enough).
glm::vec3 into_front(glm::vec3 d, glm::vec3 n) { return glm::dot(d, n) < 0.0f ? -d : d; }

// Sealed on the side `n` faces: every sample point lifted off that side sees mostly back faces of
// single-sided surfaces (trace_probe counts only RayHit::inside() hits).
bool side_sealed(const scene::RayScene& rays, std::uint32_t t, glm::vec3 n, const std::vector<glm::vec3>& sphere, float lift) {
  const scene::Scene& s = rays.scene();
  const glm::uvec3 tri = s.triangles[t];
  const glm::vec3 a = s.positions[tri.x], b = s.positions[tri.y], c = s.positions[tri.z];
  const glm::vec3 samples[] = {(a + b + c) / 3.0f, 0.8f * a + 0.1f * (b + c), 0.8f * b + 0.1f * (a + c),
                               0.8f * c + 0.1f * (a + b)};
  // Screen: most triangles are plainly visible. Every kSealScreenStride-th lattice direction (spread over
  // the hemisphere) from the centroid; if none of them meets a back face, the triangle is open without
  // the full test (which cost ten times the rest of the bvh stage on a 291k-triangle scene).
  // (No allocation on this path, which every triangle takes.)
  std::array<glm::vec3, kSealRays / kSealScreenStride> screen;
  for (std::size_t i = 0; i < screen.size(); ++i) screen[i] = into_front(sphere[i * kSealScreenStride], n);
  const glm::vec3 centroid = samples[0] + lift * n;
  if (trace_probe(rays, centroid, Cube{centroid, 0.0f}, screen).backface_hits == 0) return false;
  std::vector<glm::vec3> dirs(sphere.size());
  std::transform(sphere.begin(), sphere.end(), dirs.begin(), [&](glm::vec3 d) { return into_front(d, n); });
  for (const glm::vec3& p : samples)
    if (is_open(rays, p + lift * n, 0.0f, dirs)) return false;
  return true;
}

// A single-sided triangle is seen only from its front; a double-sided one from both sides, so it is
// sealed only when both are (a double-sided plane inside a solid, not a double-sided wall of a room).
bool triangle_sealed(const scene::RayScene& rays, std::uint32_t t, const std::vector<glm::vec3>& sphere, float lift) {
  const scene::Scene& s = rays.scene();
  const glm::vec3 n = scene::triangle_normal(s, t);
  if (n == glm::vec3(0.0f)) return false; // degenerate: nothing to see either way
  if (!side_sealed(rays, t, n, sphere, lift)) return false;
  return !scene::is_double_sided(s, t) || side_sealed(rays, t, -n, sphere, lift);
}

} // namespace

std::vector<char> sealed_triangles(const scene::RayScene& rays, int threads) {
  const scene::Scene& s = rays.scene();
  const std::vector<glm::vec3> sphere = lattice_directions(Lattice::fibonacci, kSealRays);
  const float lift = scene::ray_epsilon(s); // off the surface as the reference's rays are
  std::vector<char> sealed(s.triangles.size(), 0);
  parallel_for(sealed.size(), threads, [&](std::size_t t) { sealed[t] = triangle_sealed(rays, std::uint32_t(t), sphere, lift) ? 1 : 0; });
  return sealed;
}

std::optional<scene::Scene> without_sealed(const scene::Scene& scene, const std::vector<char>& sealed) {
  if (std::find(sealed.begin(), sealed.end(), 1) == sealed.end()) return std::nullopt;
  scene::Scene out;
  out.positions = scene.positions;
  out.materials = scene.materials;
  out.lights = scene.lights;
  out.bounds = scene.bounds; // the root cube and the clearance stay those of the whole scene
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    if (sealed[t] != 0) continue;
    out.triangles.push_back(scene.triangles[t]);
    out.triangle_material.push_back(scene.triangle_material[t]);
    out.triangle_albedo.push_back(scene.triangle_albedo[t]);
    out.triangle_emission.push_back(scene.triangle_emission[t]);
  }
  return out;
}

std::vector<PlacedProbe> place_octree(const PlacementInput& in, formats::Octree& tree, const ProgressCallback& progress) {
  const BakeSettings& s = *in.settings;
  const scene::Scene& scene = in.rays->scene();
  std::vector<formats::NodeCube> pending = {formats::root_cube(tree.volume().info)};
  std::vector<TriangleList> pending_triangles(1, TriangleList(scene.triangles.size()));
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) pending_triangles[0][t] = std::uint32_t(t);
  std::vector<PlacedProbe> placed;
  while (!pending.empty()) {
    if (progress) progress("place", double(pending.front().depth) / double(s.max_depth + 1));
    std::vector<Cube> cubes;
    std::vector<glm::vec3> centres;
    for (const auto& node : pending) {
      cubes.push_back(to_cube(node));
      centres.push_back(node.centre());
    }
    const std::vector<ProbeRays> results = trace_all(in, cubes, centres);
    std::vector<formats::NodeCube> next;
    std::vector<TriangleList> next_triangles;
    for (std::size_t i = 0; i < pending.size(); ++i) {
      const formats::NodeCube& node = pending[i];
      const float f = results[i].hit_fraction();
      const bool below_max = node.depth < s.max_depth;
      // A centre inside geometry (mostly back faces) cannot judge its node either; nor can one lying on a
      // double-sided surface (within the clearance), which has no back to tell its sides apart: half its
      // rays end at once whichever side the node's content is on.
      const bool on_double_sided = results[i].nearest_double_sided && results[i].nearest < in.clearance;
      const bool centre_blind = f < s.split_low || results[i].backface_fraction() > 0.5f || on_double_sided;
      const bool refine_towards_geometry = centre_blind && below_max && !pending_triangles[i].empty();
      if (f < s.split_low && !refine_towards_geometry) continue; // M2: the leaf stays without a probe
      if ((f >= s.split_high && below_max) || refine_towards_geometry) {
        const int meta = tree.split(node.node); // M3
        for (int octant = 0; octant < 8; ++octant) {
          formats::NodeCube child = formats::child_cube(node, octant);
          child.node = formats::child_node(meta, octant);
          next_triangles.push_back(overlapping(scene, pending_triangles[i], child));
          next.push_back(child);
        }
        continue;
      }
      const int probe = tree.place_probe(node.node); // M1 -> L2
      gpu::Probe& record = tree.volume().probes[std::size_t(probe)];
      record.hit_fraction = f;
      record.backface_fraction = results[i].backface_fraction();
      placed.push_back({probe, cubes[i], results[i]});
    }
    pending = std::move(next);
    pending_triangles = std::move(next_triangles);
  }
  return placed;
}

std::vector<PlacedProbe> place_grid(const PlacementInput& in, formats::Octree& tree, const scene::Bounds& bounds) {
  const int n = in.settings->grid_resolution;
  const glm::vec3 cell = (bounds.max - bounds.min) / float(n);
  std::vector<Cube> cubes;
  std::vector<glm::vec3> centres;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const glm::vec3 centre = bounds.min + (glm::vec3(float(x), float(y), float(z)) + 0.5f) * cell;
        const float size = std::max({cell.x, cell.y, cell.z});
        cubes.push_back({centre - glm::vec3(0.5f * size), size});
        centres.push_back(centre);
      }
  const std::vector<ProbeRays> results = trace_all(in, cubes, centres);
  // Grid probes belong to no octree node, so they are appended directly; the Octree only has to learn
  // that its probe buffer changed.
  std::vector<PlacedProbe> placed;
  auto& probes = tree.volume().probes;
  for (std::size_t i = 0; i < cubes.size(); ++i) {
    gpu::Probe record{};
    record.position = centres[i];
    record.link = ~gpu::PROBE_NO_SURFELS;
    record.node = -1;
    record.hit_fraction = results[i].hit_fraction();
    record.backface_fraction = results[i].backface_fraction();
    placed.push_back({int(probes.size()), cubes[i], results[i]});
    probes.push_back(record);
  }
  formats::sync_info_counts(tree.volume());
  tree.rebuild_free_lists();
  return placed;
}

} // namespace probebake::bake::detail
