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
#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include "method_util.h"
#include "probebake/leaf_rule.h"
#include "probebake/placement/placement.h"
#include "refine_octree.h"

namespace probebake::placement {
namespace {

// Triangles whose bounding boxes overlap a node's cube, handed down from parent to children.
using TriangleList = std::vector<std::uint32_t>;

TriangleList overlapping(const scene::Scene& s, const TriangleList& parent, const formats::NodeCube& cube) {
  TriangleList out;
  for (std::uint32_t t : parent)
    if (detail::box_overlaps_cube(s, t, cube)) out.push_back(t);
  return out;
}

Cube to_cube(const formats::NodeCube& c) { return {c.min, c.size}; }

} // namespace

bool detail::box_overlaps_cube(const scene::Scene& s, std::uint32_t t, const formats::NodeCube& c) {
  const glm::uvec3 tri = s.triangles[t];
  const glm::vec3 lo = glm::min(glm::min(s.positions[tri.x], s.positions[tri.y]), s.positions[tri.z]);
  const glm::vec3 hi = glm::max(glm::max(s.positions[tri.x], s.positions[tri.y]), s.positions[tri.z]);
  const glm::vec3 cmax = c.min + glm::vec3(c.size);
  return glm::all(glm::lessThanEqual(lo, cmax)) && glm::all(glm::greaterThanEqual(hi, c.min));
}

std::vector<PlacedProbe> place_octree(const PlacementInput& in, formats::Octree& tree, const scene::Bounds&) {
  const PlacementSettings& s = in.settings;
  if (in.refine.probe_budget > 0) return place_octree_by_error(in, tree);
  const scene::Scene& scene = in.rays->scene();
  std::vector<formats::NodeCube> pending = {formats::root_cube(tree.volume().info)};
  std::vector<TriangleList> pending_triangles(1, TriangleList(scene.triangles.size()));
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) pending_triangles[0][t] = std::uint32_t(t);
  std::vector<PlacedProbe> placed;
  while (!pending.empty()) {
    if (in.progress) in.progress(double(pending.front().depth) / double(s.max_depth + 1));
    std::vector<Cube> cubes;
    std::vector<glm::vec3> centres;
    for (const auto& node : pending) {
      cubes.push_back(to_cube(node));
      centres.push_back(node.centre());
    }
    const std::vector<ProbeRays> results = detail::trace_all(in, cubes, centres);
    std::vector<formats::NodeCube> next;
    std::vector<TriangleList> next_triangles;
    for (std::size_t i = 0; i < pending.size(); ++i) {
      const formats::NodeCube& node = pending[i];
      const float f = results[i].hit_fraction();
      // A centre inside geometry (mostly back faces) cannot judge its node either; nor can one lying on a
      // double-sided surface (within the clearance), which has no back to tell its sides apart: half its
      // rays end at once whichever side the node's content is on. The rule is the runtime's
      // (leaf_rule.h), with the bake's knowledge of the cube's triangles and its relocation step.
      const bool on_double_sided = results[i].nearest_double_sided && results[i].nearest < in.clearance;
      const bool blind =
          gpu::leaf_centre_blind(f, results[i].backface_fraction(), s.split_low, gpu::LEAF_DEAD_BACKFACE_FRACTION) ||
          on_double_sided;
      const int verdict =
          gpu::leaf_verdict_with(f, blind, !pending_triangles[i].empty(), true, node.depth, tree.volume().info);
      if (verdict == gpu::LEAF_VERDICT_FREE) continue; // M2: the leaf stays without a probe
      if (verdict == gpu::LEAF_VERDICT_SPLIT) {
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

} // namespace probebake::placement
