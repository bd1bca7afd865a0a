// Octree probe placement (octree-probe-surfel-placement-ddgi-thesis §3.2.2, state L1 and the M1-M3
// transitions it triggers), evaluated breadth-first on the CPU until the tree no longer changes.
#include "placement.h"

#include <algorithm>

#include "parallel.h"

namespace probebake::bake::detail {
namespace {

Cube to_cube(const formats::NodeCube& c) { return {c.min, c.size}; }

std::vector<ProbeRays> trace_all(const PlacementInput& in, const std::vector<Cube>& cubes,
                                 const std::vector<glm::vec3>& positions) {
  std::vector<ProbeRays> results(cubes.size());
  parallel_for(cubes.size(), in.settings->threads,
               [&](std::size_t i) { results[i] = trace_probe(*in.rays, positions[i], cubes[i], in.directions); });
  return results;
}

} // namespace

std::vector<PlacedProbe> place_octree(const PlacementInput& in, formats::Octree& tree, const ProgressCallback& progress) {
  const BakeSettings& s = *in.settings;
  std::vector<formats::NodeCube> pending = {formats::root_cube(tree.volume().info)};
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
    for (std::size_t i = 0; i < pending.size(); ++i) {
      const formats::NodeCube& node = pending[i];
      const float f = results[i].hit_fraction();
      if (f < s.split_low) continue; // M2: the leaf stays without a probe
      if (f >= s.split_high && node.depth < s.max_depth) {
        const int meta = tree.split(node.node); // M3
        for (int octant = 0; octant < 8; ++octant) {
          formats::NodeCube child = formats::child_cube(node, octant);
          child.node = formats::child_node(meta, octant);
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
