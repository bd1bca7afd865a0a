// The probe tree the memory update starts from when cells stream (docs/RUNTIME_INTERNALS.md "With
// streaming"): the file's tree with every cell's subtree collapsed to the cell's node, and pools sized by
// what the budget lets be resident at once. Cells then arrive through the pools (memory_cells.comp seats the
// file's subtree), so the device holds the probes, clusters and light records of the resident cells, not of
// the whole file.
#pragma once

#include <cstdint>
#include <span>

#include "memory_update/memory_update_pass.h"
#include "probebake/formats/probe_volume.h"
#include "probebake/streaming/cell_residency.h"

namespace probebake::runtime::detail {

// `file` (octree placement, cell_depth >= 1) as a new tree: nodes above the cell depth and the leaves there
// as the file has them (probes, surfels and all), every cell's node a leaf whose one probe, at the node's
// centre with no surfels, holds the mean irradiance of the file's probes below it: what memory_cells does to
// a cell that drops. A cell whose subtree has no probe becomes a probe-less leaf. The SVO's stencils point at
// the probes that stand for the file's (weights of a collapsed cell's probes summed). Probe and cluster
// slots are numbered afresh (no free slot between them); the leaf queue is left empty.
formats::ProbeVolume collapse_cells(const formats::ProbeVolume& file);

// Room for the file's subtrees of the cells that can be resident at once, whatever the camera does
// (streaming::most_resident of their probes and clusters over `footprints` within `budget`), for
// prepare_for_memory_update, which adds the memory update's headroom.
SeatRoom resident_seat_room(const formats::ProbeVolume& file, std::span<const streaming::CellFootprint> footprints,
                            std::uint64_t budget);

} // namespace probebake::runtime::detail
