// The bake's way to a placement method: formats::PlacementKind -> the method's function, both from the rows
// of formats/placement_methods.def, so every kind has its function (a row whose folder does not define it
// fails to link).
#include <cstddef>
#include <iterator>

#include <fmt/core.h>

#include "method_util.h"
#include "probebake/common/parallel.h"
#include "probebake/formats/error.h"
#include "probebake/placement/placement.h"

namespace probebake::placement {

namespace {

// Row i is PlacementKind(i)'s function.
constexpr PlacementMethod kMethods[] = {
#define PROBEBAKE_PLACEMENT(name, code, function, ...) &function,
#include "probebake/formats/placement_methods.def"
};

} // namespace

PlacementMethod placement_method(formats::PlacementKind kind) {
  const auto row = static_cast<std::size_t>(kind);
  if (row < std::size(kMethods)) return kMethods[row];
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
