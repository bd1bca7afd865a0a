#include "probebake/formats/placement_kind.h"

#include <array>

#include "probebake/gpu_types.h"

namespace probebake::formats {
namespace {

// Row i is PlacementKind(i) (placement_kinds_test checks it).
constexpr std::array kKinds = {
    PlacementKindInfo{PlacementKind::octree, "octree", gpu::PLACEMENT_OCTREE, true, true, false, true, 0.0f},
    PlacementKindInfo{PlacementKind::grid, "grid", gpu::PLACEMENT_GRID, false, false, true, true, 0.0f},
    PlacementKindInfo{PlacementKind::skeleton, "skeleton", gpu::PLACEMENT_SKELETON, false, false, false, true, 3.0f},
};

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
