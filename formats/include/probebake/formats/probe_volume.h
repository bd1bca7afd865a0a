// The canonical in-memory model of a baked probe volume: one member per .probes section, each laid out
// exactly as the GPU storage buffer it is copied into (shaders/include/probebake/gpu_types.h). The bake
// fills it, the .probes reader and writer convert it to and from bytes, the runtime uploads it, and
// validate() checks it, whether it came from a file or from a GPU read-back.
//
// Buffers follow the octree thesis §3.1.1-3.1.5 and the SVO of the non-uniform placement paper §4.1.
// Streaming cells (Cell) are this project's addition, see cells.h and docs/FORMAT.md.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "probebake/gpu_types.h"

namespace probebake::formats {

// A range of elements of one section that belongs to one streaming cell. byte_offset is relative to the
// start of the section's payload (first * element size); byte_size = count * element size.
struct CellRange {
  std::uint32_t first = 0;       // offset  0: index of the cell's first element in the section
  std::uint32_t count = 0;       // offset  4: elements of the cell (contiguous)
  std::uint64_t byte_offset = 0; // offset  8
  std::uint64_t byte_size = 0;   // offset 16
};                               // size 24

// One streaming cell: a cube of the regular grid that divides the root cube into (2^cell_depth)^3 cells.
// Only cells that own at least one element are stored, sorted by cell_index. See cells.h.
struct Cell {
  glm::vec3 bounds_min{0.0f};  // offset  0: world-space minimum corner of the cell cube
  std::int32_t root_node = -1; // offset 12: octree node whose cube is exactly this cell, or -1 when the
                               //            octree is not subdivided that deep there (a shallower leaf
                               //            covers the cell; find it with find_leaf)
  glm::vec3 bounds_max{0.0f};  // offset 16: world-space maximum corner
  std::int32_t cell_index = 0; // offset 28: x + n * (y + n * z), n = 2^cell_depth
  CellRange probes;            // offset 32: probes whose position lies in the cell
  CellRange surfel_batches;    // offset 56: batches owned by those probes (chain order)
  CellRange svo_leaves;        // offset 80: SVO leaf payloads of voxels inside the cell
};                             // size 104

// Where one cell's part of the static tracing tree lies (format 1.5, section cell_tracing; one record per
// Cell, same order). The static tree (trace_trees[0]) is a top level over per-cell subtrees: a cell's inner
// nodes, faces (those whose centroid lies in the cell) and vertices are contiguous and refer only to each
// other, so a reader can load or drop them alone. The top-level nodes come before every cell's nodes.
struct CellTracing {
  CellRange trace_nodes;    // offset  0: the cell subtree's inner nodes, its root first
  CellRange trace_faces;    // offset 24
  CellRange trace_vertices; // offset 48
};                          // size 72

static_assert(sizeof(CellRange) == 24 && sizeof(Cell) == 104 && sizeof(CellTracing) == 72);

// Everything a .probes file holds. Vectors that a scene does not use stay empty and are not written
// (static scenes: no surfel_batches; bakes without a runtime queue: no leaf buffer; no cells: no index).
// Counts in `info` must equal the vector sizes (validate() reports count_mismatch otherwise).
//
// Runtime lighting (format 1.1, optional sections): what a GPU light update needs to reproduce the
// bake's lighting without ray-tracing extensions. Present exactly when `lighting` is; its counts must
// equal the sizes of the five vectors after it (validate() reports lighting_sections otherwise).
struct ProbeVolume {
  gpu::VolumeInfo info{};
  std::vector<std::int32_t> octree;                 // info.octree_elements; [0] is the root
  std::vector<gpu::Probe> probes;                   // info.probe_capacity
  std::vector<gpu::SurfelBatch> surfel_batches;     // info.batch_capacity (0 for static scenes)
  gpu::LeafQueueHeader leaf_header{};               // meaningful only when leaf_entries is not empty
  std::vector<gpu::LeafEntry> leaf_entries;         // 3 * leaf_header.segment_capacity, or empty
  std::vector<std::int32_t> probe_index;            // info.probe_capacity + 1 (see rebuild_probe_index)
  std::vector<std::int32_t> svo_nodes;              // info.svo_nodes; [0] is the SVO root when not empty
  std::vector<gpu::SvoLeaf> svo_leaves;             // info.svo_leaves
  std::int32_t cell_depth = 0;                      // the cell grid is (2^cell_depth)^3; see cells.h
  std::vector<Cell> cells;                          // streaming index, or empty (load everything)
  std::vector<CellTracing> cell_tracing;            // one per cell (format 1.5), or empty: tracing not split
  std::vector<std::uint64_t> cell_checksums;        // as read from a file (format 1.6, cells.h cell_checksum), or
                                                    // empty; validate_file checks them, the writer takes the bytes' own
  std::vector<std::uint64_t> cell_global_checksums; // as read (format 1.7, cells.h cell_global_checksums_of), like them
  std::uint64_t input_hash = 0;                     // hash of the bake's inputs and settings (given by it)

  std::optional<gpu::LightingInfo> lighting;       // settings and counts of the sections below
  std::vector<glm::vec4> ray_directions;           // lighting->rays Fibonacci lighting rays, then
                                                   // placement_rays lattice directions; unit xyz, w = 0
  std::vector<gpu::BvhNode> bvh_nodes;             // 1.1-1.3 float layout, read from older files only
  std::vector<gpu::TraceTriangle> trace_triangles; // (upgrade_tracing turns them into the five below)
  std::vector<gpu::PunctualLight> punctual_lights;
  std::vector<gpu::EmitterPatch> emitter_patches;  // empty unless emissive_as_lights
  std::vector<gpu::DynamicObject> dynamic_objects; // lighting->dynamic_objects (format 1.3); empty = all static
  // Compact tracing (format 1.4, trace_mesh.h): tree 0 static, tree 1 + o dynamic object o.
  std::vector<gpu::TraceTree> trace_trees; // 1 + lighting->dynamic_objects when present
  std::vector<gpu::TraceNode> trace_nodes; // lighting->bvh_nodes
  std::vector<gpu::TraceFace> trace_faces; // lighting->triangles, in leaf order
  std::vector<gpu::TraceVertex> trace_vertices;
  std::vector<gpu::TraceMaterial> trace_materials;

  // The grid placement's lattice (format 1.8, gpu_types.h GridLatticeHeader): header words, then one point
  // word per lattice point; empty for other placements and for grids baked before 1.8.
  std::vector<std::uint32_t> grid_lattice;

  // The sky's radiance map (format 1.9, sky_section.h): header words, then RGB floats per texel; empty for a
  // constant sky (LightingInfo::sky_radiance alone).
  std::vector<std::uint32_t> sky;
};

// The three largest sections (trace_nodes, trace_faces, trace_vertices), by file index, as the validator and the
// streamed tracing read them: over a volume's own vectors, or over a file mapped for the length of a streaming
// load (CellFile::open), which then leaves those vectors empty so that host memory never holds the world.
struct TracingView {
  std::span<const gpu::TraceNode> nodes;
  std::span<const gpu::TraceFace> faces;
  std::span<const gpu::TraceVertex> vertices;
};

inline TracingView tracing_view(const ProbeVolume& volume) {
  return {volume.trace_nodes, volume.trace_faces, volume.trace_vertices};
}

// A volume with a root-only octree (one leaf without probe) and every other buffer empty; `settings`
// provides root cube, placement and bake parameters, its count fields are overwritten.
ProbeVolume make_empty_volume(const gpu::VolumeInfo& settings);

// Sets the count fields of volume.info from the vector sizes (octree, probes, batches, SVO) and, when
// the volume has lighting, those of volume.lighting (BVH nodes, triangles, lights, emitter patches).
// Throws Error(internal) when a vector holds more than INT32_MAX elements.
void sync_info_counts(ProbeVolume& volume);

// Gives the volume a leaf buffer of three segments of `segment_capacity` zeroed entries, all counts 0,
// pull origin 0.
void init_leaf_queue(ProbeVolume& volume, int segment_capacity);

} // namespace probebake::formats
