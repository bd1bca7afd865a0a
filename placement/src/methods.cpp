// The bake's way to a placement method: formats::PlacementKind -> the method's function. The switch has
// no default, so a kind added to formats/placement_kind.h without a case here fails the -Werror build.
#include <fmt/core.h>

#include "method_util.h"
#include "probebake/common/parallel.h"
#include "probebake/formats/error.h"
#include "probebake/placement/placement.h"

namespace probebake::placement {

PlacementMethod placement_method(formats::PlacementKind kind) {
  switch (kind) {
  case formats::PlacementKind::octree: return place_octree;
  case formats::PlacementKind::grid: return place_grid;
  case formats::PlacementKind::skeleton: return place_skeleton;
  }
  throw Error(ErrorKind::internal, fmt::format("placement: no method for kind {}", int(kind)));
}

std::vector<PlacedProbe> place(formats::PlacementKind kind, const PlacementInput& in, formats::Octree& tree,
                               const scene::Bounds& bounds) {
  return placement_method(kind)(in, tree, bounds);
}

namespace detail {

std::vector<ProbeRays> trace_all(const PlacementInput& in, const std::vector<Cube>& cubes,
                                 const std::vector<glm::vec3>& positions) {
  std::vector<ProbeRays> results(cubes.size());
  parallel_for(cubes.size(), in.settings.threads,
               [&](std::size_t i) { results[i] = trace_probe(*in.rays, positions[i], cubes[i], in.directions); });
  return results;
}

} // namespace detail
} // namespace probebake::placement
