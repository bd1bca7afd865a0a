// The placement methods' kinds, one per row of placement_methods.def: the name the CLI and reports use, the
// VolumeInfo.placement code a file stores, and the properties that decide which settings and invariants
// apply. Everything that used to ask "grid or octree?" asks this table instead; a new method is a row in
// placement_methods.def and its folder placement/methods/<name>/ (docs/ARCHITECTURE.md).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace probebake::formats {

enum class PlacementKind {
#define PROBEBAKE_PLACEMENT(name, ...) name,
#include "probebake/formats/placement_methods.def"
};

// A row of placement_methods.def (which documents each column), less the function.
struct PlacementKindInfo {
  PlacementKind kind;
  std::string_view name;     // as typed after --placement and printed by info / eval
  int file_code;             // VolumeInfo.placement (docs/FORMAT.md); unique per row, never renumbered
  bool has_octree;           // probes live in octree leaves (else node -1, the octree stays a bare root)
  bool uses_max_depth;       // VolumeInfo.max_depth is the method's depth limit (else 0)
  bool uses_grid_resolution; // VolumeInfo.grid_resolution is N of an N^3 grid, at most N^3 probes (else 0)
  bool meets_probe_budget;   // can be baked to about N probes (eval's --probes ladder sweeps these rows)
  // The root cube reaches this many clearances past the scene's bounds on every side (else 0.2 %), so
  // that probes fit around a solid that fills its own bounds (box_draco).
  float root_pad_clearances;
  std::string_view options; // the bake options it reads, for the CLI's --placement help
};

// Every row, in enum order.
std::span<const PlacementKindInfo> placement_kinds();
const PlacementKindInfo& placement_kind_info(PlacementKind kind);
std::string_view placement_name(PlacementKind kind);
// The kind named `name`, or nothing (names are exact, lower case).
std::optional<PlacementKind> parse_placement(std::string_view name);
// The row whose file_code is `code`, or null for a code no method writes (a corrupt or newer file).
const PlacementKindInfo* placement_kind_for_code(int code);
// "octree|grid": the names joined for help texts and error messages.
std::string placement_names(std::string_view separator = "|");

} // namespace probebake::formats
