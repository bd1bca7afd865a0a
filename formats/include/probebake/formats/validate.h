// The validator: every invariant of the octree thesis §3.1.1-3.1.5 and of the SVO probe index (non-uniform
// placement paper §4.1), plus counts, cells, finiteness and the runtime lighting sections (format 1.1: the
// BVH the GPU traverses, lights, patches). validate() works on a ProbeVolume, so the same
// checks run on file contents and on buffers read back from the GPU runtime; validate_file() checks the
// container first. Cheap structural checks run first, deep ones (traversals, per-element scans) after.
//
// Invariant ids are stable snake_case names (docs/FORMAT.md, "Validation"); tools and tests match on them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "probebake/formats/probe_volume.h"
#include "probebake/formats/trace_mesh.h"

namespace probebake::formats {

struct Violation {
  std::string invariant; // e.g. "octree_cycle"
  std::string section;   // "octree", "probes", ..., "header", "section_table", "container"
  long long index = -1;  // element index inside the section, -1 when not about one element
  std::string message;   // one line
};

struct ValidationReport {
  std::string name;              // file name or "volume"
  bool readable = true;          // false: the bytes are not a .probes file we can decode
  bool truncated = false;        // stopped at ValidateOptions::max_errors
  std::size_t cells_checked = 0; // cells whose bytes were checked on their own against their checksum (1.6)
  std::vector<Violation> violations;
  bool valid() const { return readable && violations.empty(); }
};

// Bounds of VolumeInfo settings that the format itself does not fix by a struct size (docs/FORMAT.md,
// "Constants"); the bake's own option limits are the same.
inline constexpr int kMaxGridResolution = 256;
inline constexpr int kMaxSurfelsPerProbe = 65536;

struct ValidateOptions {
  std::size_t max_errors = 1000;  // stop after this many violations (0 = no limit)
  float position_epsilon = 1e-4f; // probe-in-cube tolerance, relative to the cube size
  float weight_tolerance = 1e-4f; // |sum of SVO weights - 1| allowed
};

ValidationReport validate(const ProbeVolume& volume, const ValidateOptions& options = {});
// The same checks with the volume's trace nodes, faces and vertices read through `tracing` instead of its
// vectors (a streaming load's, CellFile::open: the file's sections in its mapping).
ValidationReport validate(const ProbeVolume& volume, const TracingView& tracing, const ValidateOptions& options = {});

// Where the static tracing tree enters cell record k's part (format 1.5 cell_tracing): the top-level word that
// leads to it (its first node, or for a cell without nodes the leaf of its faces), that word's depth, and
// the box that every box above it narrows to as the GPU decodes them. Recorded by validate_without_cells.
struct CellEntry {
  std::uint32_t word = 0;
  int depth = 0;
  TraceBox box{};
  bool reached = false;
};

// validate() for a streaming load that has read a file's global part and none of the cells' own trace
// nodes, faces and vertices (format 1.7: docs/FORMAT.md section 6.2): their elements in `tracing` are never
// read. Every invariant is checked but those of the cells' own tracing, which validate_cell_tracing checks
// as each cell arrives. `entries` gets one CellEntry per cell record. The volume needs cell_tracing.
ValidationReport validate_without_cells(const ProbeVolume& volume, const TracingView& tracing,
                                        std::vector<CellEntry>& entries, const ValidateOptions& options = {});
// Cell record k's own trace nodes, faces and vertices (`cell`: its three ranges' elements, numbered as in the
// file) against what validate() checks of them: finite vertices; faces with vertices and material in range
// and non-zero area (lighting_values); nothing outside the cell (cell_tracing); its subtree from entries[k],
// every node reached once and every face in one leaf inside every box above it (trace_tree). `volume` and
// `entries` as validate_without_cells passed and left them; of `volume` it reads only info, cell_depth, cells,
// cell_tracing, trace_trees and trace_materials (what CellFile keeps). A volume and its cells that pass both
// pass validate() (tests/formats/validate_test.cpp, fuzz_probes_reader).
ValidationReport validate_cell_tracing(const ProbeVolume& volume, std::span<const CellEntry> entries, std::size_t k,
                                       const TracingView& cell, const ValidateOptions& options = {});

// Container checks (readable = false and a "container" violation when the bytes cannot be decoded;
// "checksum" violations for mismatches; format_version, section_flags, section_layout, trailing_bytes and
// section_dependency for what the reader reads but the format does not allow), then validate() on the
// decoded volume, then each cell on its own against its checksum (1.6: cell_checksum, cells_checked). The
// trace nodes, faces and vertices are checked in place in `bytes` when those are 16-byte aligned (a file's
// mapping: file_mapping.h), so that they are never copied; otherwise they are decoded.
ValidationReport validate_file(std::span<const std::uint8_t> bytes, std::string_view name,
                               const ValidateOptions& options = {});

// Every invariant id the validator can report, with a one-line description (docs/FORMAT.md lists the
// same ids; a test keeps them in step).
struct InvariantInfo {
  const char* id;
  const char* description;
};
std::span<const InvariantInfo> invariants();

// "<section>[<index>]: <invariant>: <message>" (or "<section>: ..." without an index).
std::string format_violation(const Violation& violation);
// "<section>[<index>]" or "<section>": where a violation is.
std::string violation_place(const Violation& violation);

// {"file", "valid", "readable", "truncated", "violation_count", "violations": [{"invariant", "section",
// "index", "message"}]}
nlohmann::json report_to_json(const ValidationReport& report);

} // namespace probebake::formats
