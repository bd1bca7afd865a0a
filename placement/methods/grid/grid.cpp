// Uniform grid placement, the baseline: N^3 probes at the cell centres of the scene bounds, in lattice order
// (formats/grid_lattice.h: the bake stores the lattice for the grid engine's lookup).
#include <algorithm>

#include "method_util.h"
#include "probebake/formats/grid_lattice.h"
#include "probebake/placement/placement.h"

namespace probebake::placement {

std::vector<PlacedProbe> place_grid(const PlacementInput& in, formats::Octree& tree, const scene::Bounds& bounds) {
  const int n = in.settings.grid_resolution;
  const gpu::GridLatticeHeader lattice = formats::grid_lattice_frame(bounds.min, bounds.max, n);
  const glm::vec3 cell = lattice.spacing;
  std::vector<Cube> cubes;
  std::vector<glm::vec3> centres;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const glm::vec3 centre = formats::grid_point_position(lattice, x, y, z);
        const float size = std::max({cell.x, cell.y, cell.z});
        cubes.push_back({centre - glm::vec3(0.5f * size), size});
        centres.push_back(centre);
      }
  const std::vector<ProbeRays> results = detail::trace_all(in, cubes, centres);
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

} // namespace probebake::placement
