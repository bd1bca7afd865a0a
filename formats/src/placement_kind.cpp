#include "probebake/formats/placement_kind.h"

#include <array>

#include "probebake/gpu_types.h"

namespace probebake::formats {
namespace {

// Row i is PlacementKind(i): both come from the rows of placement_methods.def, in order.
constexpr std::array kKinds = {
// clang-format off
#define PROBEBAKE_PLACEMENT(name, code, function, has_octree, uses_max_depth, uses_grid_resolution, \
                            meets_probe_budget, root_pad_clearances, options)                       \
  PlacementKindInfo{PlacementKind::name, #name, code, has_octree, uses_max_depth, uses_grid_resolution, \
                    meets_probe_budget, root_pad_clearances, options},
// clang-format on
#include "probebake/formats/placement_methods.def"
};

constexpr bool codes_unique() {
  for (std::size_t i = 0; i < kKinds.size(); ++i)
    for (std::size_t j = i + 1; j < kKinds.size(); ++j)
      if (kKinds[i].file_code == kKinds[j].file_code) return false;
  return true;
}
static_assert(codes_unique(), "placement_methods.def: two rows share a file code");
// The codes the GPU side names (gpu_types.h PLACEMENT_*: the runtime and the renderer ask for the octree) are
// the table's.
static_assert(kKinds[std::size_t(PlacementKind::octree)].file_code == gpu::PLACEMENT_OCTREE);
static_assert(kKinds[std::size_t(PlacementKind::grid)].file_code == gpu::PLACEMENT_GRID);
static_assert(kKinds[std::size_t(PlacementKind::skeleton)].file_code == gpu::PLACEMENT_SKELETON);

} // namespace

std::span<const PlacementKindInfo> placement_kinds() { return kKinds; }

const PlacementKindInfo& placement_kind_info(PlacementKind kind) { return kKinds.at(static_cast<std::size_t>(kind)); }

std::string_view placement_name(PlacementKind kind) { return placement_kind_info(kind).name; }

std::optional<PlacementKind> parse_placement(std::string_view name) {
  for (const PlacementKindInfo& k : kKinds)
    if (k.name == name) return k.kind;
  return std::nullopt;
}

const PlacementKindInfo* placement_kind_for_code(int code) {
  for (const PlacementKindInfo& k : kKinds)
    if (k.file_code == code) return &k;
  return nullptr;
}

std::string placement_names(std::string_view separator) {
  std::string out;
  for (const PlacementKindInfo& k : kKinds) {
    if (!out.empty()) out += separator;
    out += k.name;
  }
  return out;
}

} // namespace probebake::formats
