// The skeleton method's entry for the bake (placement.h's PlacementMethod): skeleton_probes() inside the
// root cube, then the probes appended like grid probes (node -1, depth 0), each with a cube of 4 x the
// clearance around it in which relocation may move it if the lattice finds it dead.
#include <algorithm>

#include "method_util.h"
#include "probebake/placement/placement.h"
#include "skeleton.h"

namespace probebake::placement {

std::vector<PlacedProbe> place_skeleton(const PlacementInput& in, formats::Octree& tree, const scene::Bounds&) {
  const formats::NodeCube root = formats::root_cube(tree.volume().info);
  SkeletonOptions options;
  options.clearance = in.clearance;
  options.probes = in.settings.probes;
  options.threads = in.settings.threads;
  options.domain.min = root.min;
  options.domain.max = root.min + glm::vec3(root.size);
  if (in.progress) in.progress(0.0);
  const SceneSdf sdf(in.rays->scene(), skeleton_sdf_settings(options.domain));
  const SkeletonResult result = skeleton_probes(*in.rays, sdf, options);

  std::vector<Cube> cubes;
  for (const glm::vec3& p : result.probes) {
    // Inside the root cube, as the validator requires of node -1 probes.
    const float size = std::min(4.0f * in.clearance, root.size);
    const glm::vec3 lo = glm::clamp(p - glm::vec3(0.5f * size), root.min, root.min + glm::vec3(root.size - size));
    cubes.push_back({lo, size});
  }
  const std::vector<ProbeRays> rays = detail::trace_all(in, cubes, result.probes);
  std::vector<PlacedProbe> placed;
  auto& probes = tree.volume().probes;
  for (std::size_t i = 0; i < cubes.size(); ++i) {
    gpu::Probe record{};
    record.position = result.probes[i];
    record.link = ~gpu::PROBE_NO_SURFELS;
    record.node = -1;
    record.hit_fraction = rays[i].hit_fraction();
    record.backface_fraction = rays[i].backface_fraction();
    placed.push_back({int(probes.size()), cubes[i], rays[i]});
    probes.push_back(record);
  }
  formats::sync_info_counts(tree.volume());
  tree.rebuild_free_lists();
  if (in.progress) in.progress(1.0);
  return placed;
}

} // namespace probebake::placement
