// The split bake (issue #15, docs/BAKE_JOBS.md): `probebake bake --cells LIST` runs, for the triangles of
// some streaming cells, the per-triangle work of the bake (the sealed test, placement/sealed.h); `probebake
// merge` takes the parts' results instead of doing that work and runs the stages that couple cells. The
// merged file is byte for byte the single-process bake's, because both run the same functions on the
// same triangles.
//
// A part numbers its cells in the bake's cell grid over the scene's root cube as volume_info gives it
// (before placement may widen the root around a closed object: the partition only has to cover every
// triangle once, whatever grid the file ends with).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "probebake/bake/bake.h"
#include "probebake/formats/bake_part.h"
#include "probebake/scene/scene.h"

namespace probebake::bake {

// The depth of the grid parts number their cells in: (2^depth)^3 cells.
int part_cell_depth(const scene::Scene& scene, const BakeSettings& settings);

// What the parts and the merge of one bake must agree on: the scene and the settings, with the part grid.
std::uint64_t part_input_hash(const scene::Scene& scene, const BakeSettings& settings);

// The part of the bake for `cells` (any cells of the part grid, ascending; cells without triangles
// contribute nothing). Throws Error(usage) for a cell outside the grid.
formats::BakePart bake_part(const scene::Scene& scene, const BakeSettings& settings,
                            std::span<const std::int32_t> cells);

// The work the parts did, for bake(): every triangle must lie in a cell that exactly one part baked.
// `names` names the parts in messages. Throws Error(input, "<name>: <reason>") for a part of another scene
// or settings, a cell two parts baked, or Error(input) naming a cell with triangles that no part baked.
PrecomputedWork merge_parts(const scene::Scene& scene, const BakeSettings& settings,
                            std::span<const formats::BakePart> parts, std::span<const std::string> names);

} // namespace probebake::bake
