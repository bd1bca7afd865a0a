// The .probes container: a fixed header, a section table, then aligned section payloads. Everything is
// little-endian; payload bytes are exactly the GPU buffer bytes. docs/FORMAT.md is the specification
// (its offset tables are checked against these structs by tests/formats/format_doc_test.cpp).
//
// This header is the container level only (no knowledge of what sections mean); probes_file.h maps a
// ProbeVolume onto it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "probebake/formats/format_version.h"

namespace probebake::formats {

// File header, at offset 0. 64 bytes in version 1.x; header_size lets a later minor version append
// fields (a 1.0 reader skips them, and still covers them with the header checksum).
struct FileHeader {
  char magic[8];                    // offset  0: the kind's magic (kProbesContainer: "PROBEBK\0")
  std::uint16_t version_major;      // offset  8: a reader refuses any other major
  std::uint16_t version_minor;      // offset 10: compatible additions
  std::uint32_t header_size;        // offset 12: bytes of this header, >= 64, multiple of 8
  std::uint32_t required_features;  // offset 16: feature bits a reader must understand (none in 1.0)
  std::uint32_t section_count;      // offset 20: entries in the section table
  std::uint32_t section_entry_size; // offset 24: bytes per section table entry (48 in 1.x)
  std::uint32_t cell_depth;         // offset 28: streaming cell grid depth (see cells.h), 0 without cells
  std::uint64_t input_hash;         // offset 32: hash of the bake inputs and settings
  std::uint64_t file_size;          // offset 40: total bytes of the file
  std::uint64_t reserved;           // offset 48: 0
  std::uint64_t header_checksum;    // offset 56: XXH3-64 of header bytes [0, 56) ++ [64, header_size) ++ table
};
static_assert(sizeof(FileHeader) == 64);

// One section table entry; the table follows the header (offset header_size).
struct SectionEntry {
  std::uint32_t type;          // offset  0: SectionType
  std::uint32_t flags;         // offset  4: kSectionRequired | ...
  std::uint64_t offset;        // offset  8: payload offset from the file start, multiple of alignment
  std::uint64_t size;          // offset 16: payload bytes = element_size * element_count
  std::uint32_t alignment;     // offset 24: power of two, 16..4096
  std::uint32_t element_size;  // offset 28: bytes per element
  std::uint64_t element_count; // offset 32
  std::uint64_t checksum;      // offset 40: XXH3-64 (seed 0) of the payload bytes
};
static_assert(sizeof(SectionEntry) == 48);

// A reader that does not know a section's type skips it when this flag is clear and refuses the file
// when it is set.
inline constexpr std::uint32_t kSectionRequired = 1u;
inline constexpr std::uint32_t kKnownSectionFlags = kSectionRequired;
// Required-feature bits known to this reader (none are defined in 1.0).
inline constexpr std::uint32_t kKnownRequiredFeatures = 0u;
inline constexpr std::uint32_t kSectionAlignment = 16;
inline constexpr std::uint32_t kMaxSectionAlignment = 4096;
// Upper bound on table entries, so that a hostile count cannot make a reader loop long.
inline constexpr std::uint32_t kMaxSections = 1024;

enum class SectionType : std::uint32_t {
  volume_info = 1,       // gpu::VolumeInfo x 1
  octree = 2,            // int32 x info.octree_elements
  probes = 3,            // gpu::Probe x info.probe_capacity
  surfel_batches = 4,    // gpu::SurfelBatch x info.batch_capacity
  leaf_queue_header = 5, // gpu::LeafQueueHeader x 1
  leaf_entries = 6,      // gpu::LeafEntry x 3 * segment_capacity
  probe_index = 7,       // int32 x (probe_capacity + 1)
  svo_nodes = 8,         // int32 x info.svo_nodes
  svo_leaves = 9,        // gpu::SvoLeaf x info.svo_leaves
  cells = 10,            // Cell x cells (optional: a reader may load everything instead)
  // Runtime lighting (1.1), all optional: a 1.0 reader skips them.
  lighting_info = 11,   // gpu::LightingInfo x 1
  ray_directions = 12,  // vec4 x (lighting.rays + lighting.placement_rays)
  bvh_nodes = 13,       // gpu::BvhNode x lighting.bvh_nodes
  trace_triangles = 14, // gpu::TraceTriangle x lighting.triangles
  punctual_lights = 15, // gpu::PunctualLight x lighting.lights
  emitter_patches = 16, // gpu::EmitterPatch x lighting.emitter_patches
  // Dynamic objects (1.3), optional.
  dynamic_objects = 17, // gpu::DynamicObject x lighting.dynamic_objects
  // Compact tracing (1.4), REQUIRED when present: they replace bvh_nodes and trace_triangles, which a
  // 1.3 reader would need, so it must refuse the file rather than trace nothing.
  trace_trees = 18,     // gpu::TraceTree x (1 + lighting.dynamic_objects)
  trace_nodes = 19,     // gpu::TraceNode x lighting.bvh_nodes
  trace_faces = 20,     // gpu::TraceFace x lighting.triangles
  trace_vertices = 21,  // gpu::TraceVertex
  trace_materials = 22, // gpu::TraceMaterial
  // Cells of the static tracing tree (1.5), optional like cells: a 1.4 reader traces the same tree.
  cell_tracing = 23, // CellTracing x cells
  // A checksum per cell (1.6), optional: what a reader that loads one cell checks its bytes against.
  cell_checksums = 24, // uint64 x cells
  // The global part's checksums (1.7), optional: what a streaming load that reads no cell checks.
  cell_global_checksums = 25, // uint64 x 6 (cells.h kCellSplitSections)
  // The grid placement's lattice (1.8), optional: a reader without it looks grid probes up through the SVO.
  grid_lattice = 26, // uint32 x (GRID_LATTICE_HEADER_WORDS + GRID_POINT_WORDS * resolution^3), gpu_types.h
  // The sky's radiance map (1.9), optional: without it rays that leave the scene see LightingInfo::sky_radiance.
  sky = 27, // uint32 x (SKY_HEADER_WORDS + 3 x width x height), sky_map.h
};
inline constexpr std::uint32_t kSectionTypeCount = 27;

inline constexpr bool is_known_section_type(std::uint32_t type) { return type >= 1 && type <= kSectionTypeCount; }

// The streaming cell index (cells, cell_tracing, cell_checksums, cell_global_checksums): data for the reader
// that loads a file cell by cell, not for the GPU.
inline constexpr bool is_cell_index_section(SectionType type) {
  return type == SectionType::cells || type == SectionType::cell_tracing || type == SectionType::cell_checksums ||
         type == SectionType::cell_global_checksums;
}

// The lowest minor version that a section of this type needs (the lighting sections came in 1.1, dynamic
// objects in 1.3, compact tracing in 1.4, cell tracing in 1.5, cell checksums in 1.6);
// unknown types need none. The writer and the validator's format_version both use it.
inline constexpr std::uint16_t minor_version_for_section(std::uint32_t type) {
  if (!is_known_section_type(type)) return 0;
  if (type == static_cast<std::uint32_t>(SectionType::sky)) return kSkyMinor;
  if (type == static_cast<std::uint32_t>(SectionType::grid_lattice)) return kGridLatticeMinor;
  if (type == static_cast<std::uint32_t>(SectionType::cell_global_checksums)) return kCellGlobalChecksumsMinor;
  if (type == static_cast<std::uint32_t>(SectionType::cell_checksums)) return kCellChecksumsMinor;
  if (type == static_cast<std::uint32_t>(SectionType::cell_tracing)) return kCellTracingMinor;
  if (type >= static_cast<std::uint32_t>(SectionType::trace_trees)) return kCompactTracingMinor;
  if (type >= static_cast<std::uint32_t>(SectionType::dynamic_objects)) return kDynamicObjectsMinor;
  return type >= static_cast<std::uint32_t>(SectionType::lighting_info) ? kLightingSectionsMinor : std::uint16_t{0};
}

// Sections a reader must understand carry kSectionRequired: those a 1.0 reader needs (volume_info to
// svo_leaves) and the compact tracing of 1.4 (a 1.3 reader would find no geometry); cells and the sections
// of 1.1-1.3 are optional, so that older readers skip them. The writer and the validator both use it.
inline constexpr bool is_required_section_type(std::uint32_t type) {
  return (type >= 1 && type <= static_cast<std::uint32_t>(SectionType::svo_leaves)) ||
         (type >= static_cast<std::uint32_t>(SectionType::trace_trees) &&
          type <= static_cast<std::uint32_t>(SectionType::trace_materials));
}

// "octree", "probes", ...; "section_<id>" for unknown types.
std::string section_name(std::uint32_t type);

// What a container holds: a .probes file, or a part of a split bake (bake_part.h), which has its own magic
// and section types so that neither reader mistakes one for the other.
struct ContainerKind {
  char magic[8];
  const char* description;                           // "a .probes file", for "not <description> (bad magic)"
  std::string (*section_name)(std::uint32_t type);   // for messages
  bool (*is_known_section_type)(std::uint32_t type); // an unknown type with kSectionRequired is refused
};
inline constexpr ContainerKind kProbesContainer{
    {'P', 'R', 'O', 'B', 'E', 'B', 'K', '\0'}, "a .probes file", section_name, is_known_section_type};

// A section to write.
struct SectionPayload {
  std::uint32_t type = 0;
  std::uint32_t flags = 0;
  std::uint32_t element_size = 1;
  std::uint64_t element_count = 0;
  std::span<const std::uint8_t> bytes; // element_size * element_count bytes
};

struct ContainerHeaderFields {
  std::uint32_t cell_depth = 0;
  std::uint64_t input_hash = 0;
  std::uint16_t version_minor = kFormatVersionMinor; // write_probes: the lowest minor the sections need
};

// Writes header, table and payloads (in the given order, each aligned to kSectionAlignment, padding
// zero). Throws Error(internal) when a payload's size disagrees with element_size * element_count.
std::vector<std::uint8_t> write_container(const ContainerHeaderFields& fields, std::span<const SectionPayload> sections,
                                          const ContainerKind& kind = kProbesContainer);

// A parsed container: a view on the caller's bytes (they must outlive it).
struct ContainerView {
  FileHeader header{};
  std::vector<SectionEntry> sections;                  // in table order
  std::vector<std::span<const std::uint8_t>> payloads; // same order
};

// Called for a checksum mismatch: `section` is "header" or the section's name, `index` its table index
// (-1 for the header), `message` the reason (without file name and place). When no callback is given, a mismatch throws like every other problem.
using ChecksumMismatch = std::function<void(const std::string& section, long long index, const std::string& message)>;

// Parses and checks the container, cheap checks first: size >= header, magic, major version, header
// size, required features, file size, table bounds, per-entry type/flags/alignment/bounds/overlap,
// element sizes, zero padding outside payloads; then checksums (header, then every section, also unknown
// ones). Throws Error(input, "<name>: <place>: <reason>"). Safe on any bytes: every field is checked
// before it is used and no allocation is sized by an unchecked field.
ContainerView parse_container(std::span<const std::uint8_t> bytes, std::string_view name,
                              const ChecksumMismatch& on_checksum_mismatch = {},
                              const ContainerKind& kind = kProbesContainer);

// parse_container without the checksums of the sections of the `unread` types, whose payloads the caller
// has not read (a streaming load, cell_file.h, which checks their global part by cell_global_checksums and
// each cell by its cell checksum). Every other check is made; a mismatch throws.
ContainerView parse_container_without(std::span<const std::uint8_t> bytes, std::string_view name,
                                      std::span<const SectionType> unread);

// XXH3-64 with seed 0, the checksum of every section and of the header.
std::uint64_t checksum64(std::span<const std::uint8_t> bytes);

// Whether the container's table lists a section of `type`.
bool has_section(const ContainerView& container, SectionType type);

} // namespace probebake::formats
