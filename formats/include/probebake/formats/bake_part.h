// A part of a split bake (issue #15, docs/FORMAT.md "Bake parts"): what `probebake bake --cells LIST` computed
// for the triangles of some streaming cells, for `probebake merge` to put in place of that work. Same
// container as .probes (header, table, checksums) with its own magic and section types, so neither
// reader takes one for the other. The cells here are those of the bake's own cell grid over the scene's
// bounds; a triangle belongs to the cell of its centroid (cells.h cell_of_triangle).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "probebake/formats/container.h"

namespace probebake::formats {

enum class PartSectionType : std::uint32_t {
  part_info = 1,   // PartInfo x 1
  part_cells = 2,  // int32 x info.cell_count: the cells baked, ascending
  part_sealed = 3, // uint8 x info.tested_triangles: 1 for a sealed triangle (placement/sealed.h), in scene order
};
inline constexpr std::uint32_t kPartSectionTypeCount = 3;

struct PartInfo {
  std::uint32_t scene_triangles;  // triangles of the whole scene
  std::uint32_t cell_count;       // entries of part_cells
  std::uint32_t tested_triangles; // the scene's triangles whose centroid lies in those cells
  std::uint32_t reserved;         // 0
};
static_assert(sizeof(PartInfo) == 16);

std::string part_section_name(std::uint32_t type);
inline constexpr bool is_known_part_section_type(std::uint32_t type) {
  return type >= 1 && type <= kPartSectionTypeCount;
}
inline constexpr ContainerKind kPartContainer{
    {'P', 'B', 'P', 'A', 'R', 'T', '1', '\0'}, "a probebake bake part", part_section_name, is_known_part_section_type};

struct BakePart {
  std::uint64_t input_hash = 0; // bake_input_hash of the scene and the settings asked for
  int cell_depth = 0;           // the cell grid the cells are numbered in, [0, cells.h kMaxCellDepth]
  std::uint32_t scene_triangles = 0;
  std::vector<std::int32_t> cells;  // ascending
  std::vector<std::uint8_t> sealed; // one per triangle of those cells, in scene order
};

std::vector<std::uint8_t> write_bake_part(const BakePart& part);
// Untrusted bytes: the container checks, then every field (cells ascending and inside the grid, flags 0 or
// 1, counts consistent). Throws Error(input, "<name>: <place>: <reason>").
BakePart read_bake_part(std::span<const std::uint8_t> bytes, std::string_view name);
BakePart read_bake_part_file(const std::filesystem::path& path);

} // namespace probebake::formats
