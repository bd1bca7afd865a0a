// Streaming cells: the root cube is divided into a regular grid of n^3 cells, n = 2^cell_depth
// (cell_depth 0: one cell; 1: up to 8). The bulky per-element sections -- probes, surfel batches, SVO
// leaf payloads -- are reordered so that each cell's elements are contiguous; a Cell record lists the
// ranges, so a reader can load or drop one cell's byte ranges. The small global sections (volume info,
// octree, probe index, leaf buffer, SVO nodes) are always loaded whole.
//
// Membership rules (the validator checks the same ones, through the same functions):
//  - a probe belongs to the cell containing its position (cell_of_point);
//  - a surfel batch belongs to the cell of its owning probe;
//  - an SVO leaf payload belongs to the cell containing its voxel's minimum corner (exact integer math
//    on voxel coordinates; voxels at or below the cell depth lie inside exactly one cell).
// Free elements (and unreferenced SVO leaves) are placed after all cells and belong to none.
// Only cells owning at least one element get a record; records are sorted by cell_index.
// Since format 1.5 the static tracing tree may be split by cell too (CellTracing, probe_volume.h): a face
// belongs to the cell containing its centroid; such cells get a record even without probes.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/formats/container.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::formats {

// Deepest supported cell grid: 32^3 cells.
inline constexpr int kMaxCellDepth = 5;

// Cells per axis for a cell depth (1 << depth).
constexpr int cells_per_axis(int cell_depth) { return 1 << cell_depth; }
// Cells of the grid: cells_per_axis^3.
constexpr int cell_count(int cell_depth) {
  return cells_per_axis(cell_depth) * cells_per_axis(cell_depth) * cells_per_axis(cell_depth);
}

// Linear index x + n * (y + n * z) of the cell containing `point`: per axis
// floor((p - root_min) / root_size * n) clamped to [0, n - 1] (non-finite coordinates map to 0).
int cell_of_point(const gpu::VolumeInfo& info, int cell_depth, glm::vec3 point);

// Cell of a triangle: the cell of its centroid (a + b + c) / 3, computed in float exactly so.
int cell_of_triangle(const gpu::VolumeInfo& info, int cell_depth, glm::vec3 a, glm::vec3 b, glm::vec3 c);

// World-space bounds of cell `cell_index`.
void cell_bounds(const gpu::VolumeInfo& info, int cell_depth, int cell_index, glm::vec3& min, glm::vec3& max);

// The octree node whose cube is exactly the cell, or -1 (see Cell::root_node). Assumes a valid octree.
int cell_root_node(const ProbeVolume& volume, int cell_depth, int cell_index);

// Cell of every SVO leaf payload (-1 for a payload no voxel references), by walking the SVO.
// Throws Error(input) when the SVO is not a tree.
std::vector<int> svo_leaf_cells(const ProbeVolume& volume, int cell_depth);

// Reorders probes, surfel batches and SVO leaves by cell (stable: original order inside a cell), remaps
// every link (octree probe links, probe <-> batch links, SVO payload and probe indices), rebuilds the
// probe index, sets volume.cell_depth and fills volume.cells (and cell_tracing, keeping the tracing ranges
// the volume's cells already carry when the depth is theirs: the bake's gpu_scene stage sets them; at another
// depth cell_tracing is dropped; cell_checksums, a file's, are cleared). The leaf buffer is not affected (it holds
// node indices). Precondition: the volume is valid (validate() clean); an Octree working on it must
// rebuild_free_lists() afterwards. Throws Error(usage) for a cell_depth outside [0, kMaxCellDepth].
void arrange_cells(ProbeVolume& volume, int cell_depth);

// Bytes of a cell's three tracing ranges (trace nodes, faces, vertices): what streaming reads per cell.
inline std::uint64_t cell_tracing_bytes(const CellTracing& t) {
  return t.trace_nodes.byte_size + t.trace_faces.byte_size + t.trace_vertices.byte_size;
}

// Bytes of cell k's own ranges (probes, surfel batches, SVO payloads and, with cell_tracing, its trace
// nodes, faces and vertices): what loading the cell alone reads beyond the global sections.
std::uint64_t cell_bytes(const ProbeVolume& volume, std::size_t k);

// XXH3-64 of cell k's own bytes: its probes, surfel batches and SVO leaf payloads, then (with cell_tracing)
// its trace nodes, faces and vertices, each range's bytes in that order (format 1.6, cell_checksums): what a
// reader that loads the cell alone checks it against. The ranges must lie inside their sections.
std::uint64_t cell_checksum(const ProbeVolume& volume, std::size_t k);
// The same with the trace nodes, faces and vertices read through `tracing` (a streaming load's).
std::uint64_t cell_checksum(const ProbeVolume& volume, const TracingView& tracing, std::size_t k);
// Every cell's checksum when the tracing is split by cell (what the writer stores), else none.
std::vector<std::uint64_t> cell_checksums_of(const ProbeVolume& volume);

// The sections whose elements are ordered by cell, in the order of cell_global_checksums (format 1.7).
inline constexpr SectionType kCellSplitSections[] = {SectionType::probes,      SectionType::surfel_batches,
                                                     SectionType::svo_leaves,  SectionType::trace_nodes,
                                                     SectionType::trace_faces, SectionType::trace_vertices};
// For each of kCellSplitSections, the XXH3-64 of its bytes outside every cell's range, in file order (the
// global part, which a streaming load reads whole): the top level and the dynamic objects' trees, free
// probes... With the trace nodes, faces and vertices read through `tracing`; the cells' ranges must lie
// inside their sections in ascending order (Error(internal) otherwise). None without cell_tracing.
std::vector<std::uint64_t> cell_global_checksums_of(const ProbeVolume& volume, const TracingView& tracing);

// Removes the streaming index (cells empty, cell_depth 0); element order is kept.
void clear_cells(ProbeVolume& volume);

} // namespace probebake::formats
