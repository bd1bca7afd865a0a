// The validator driver: runs the phases of validate_*.cpp cheap-first, stops at max_errors, and reports
// in text and JSON. validate_file() checks the container first (NanoVDB-style: magic, version and sizes
// before checksums, checksums before the model).
#include "probebake/formats/validate.h"

#include <cstdint>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "probebake/formats/container.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "validate_internal.h"

namespace probebake::formats {
namespace {

void run_phases(const ProbeVolume& volume, const TracingView& tracing, const detail::DeferredCells* deferred,
                detail::Reporter& out) {
  try {
    detail::check_volume_info(volume, out);
    detail::check_counts(volume, out);
    detail::check_dependencies(volume, out);
    detail::check_finite(volume, out);
    const detail::OctreeFacts octree = detail::check_octree(volume, out);
    detail::check_probes(volume, octree, out);
    detail::check_surfel_batches(volume, out);
    detail::check_probe_index(volume, out);
    detail::check_leaf_queue(volume, octree, out);
    detail::check_svo(volume, out);
    detail::check_grid_lattice(volume, out);
    detail::check_cells(volume, tracing, octree, deferred, out);
    detail::check_lighting(volume, tracing, deferred, out);
    detail::check_sky(volume, out);
  } catch (const detail::StopValidation&) {
    // max_errors reached; the report says truncated
  }
}

constexpr InvariantInfo kInvariants[] = {
    {"container", "the bytes are not a readable .probes container (magic, version, sizes, table)"},
    {"checksum", "a section's or the header's XXH3-64 checksum does not match"},
    {"format_version", "the minor version covers the file's section types and flags; a known minor has a 64-byte "
                       "header and 48-byte table entries"},
    {"section_flags",
     "a known section's REQUIRED flag is the one docs/FORMAT.md gives its type; reserved flag bits are zero"},
    {"section_layout",
     "no empty known section; each payload starts at the first multiple of its alignment after the previous one"},
    {"trailing_bytes", "the file ends right after the last payload"},
    {"section_dependency",
     "no section without the one it needs: surfel batches need probes, SVO leaves SVO nodes, leaf header <-> entries"},
    {"volume_info", "VolumeInfo settings in range (root size, placement, depths, lattice, thresholds, padding)"},
    {"cell_depth", "the cell grid depth is within [0, kMaxCellDepth], and 0 when allocated probes have no cells"},
    {"grid_resolution",
     "grid placement: 1 <= N <= kMaxGridResolution and at most N^3 allocated probes; octree placement: 0"},
    {"count_mismatch",
     "VolumeInfo counts equal the buffer sizes; probe index = capacity + 1; leaf buffer = 3 segments"},
    {"non_finite", "every float is finite"},
    {"octree_root", "the octree buffer holds the root at index 0"},
    {"incomplete_cluster_used", "the incomplete trailing cluster is all zero and never a child"},
    {"grid_octree", "grid placement: the octree is a single probe-less root"},
    {"free_not_zeroed", "free clusters, probes, batches and SVO payloads have zeroed links"},
    {"node_sign", "meta elements are never positive"},
    {"meta_parent_mismatch", "a meta element holds ~parent, and that parent points back at the cluster"},
    {"octree_child_range", "a parent's value is the meta index of a cluster inside the buffer"},
    {"octree_two_parents", "no cluster is the child of two nodes"},
    {"octree_cycle", "no cluster is a descendant of itself"},
    {"octree_unreachable", "every allocated cluster is reachable from the root"},
    {"octree_too_deep", "no node is deeper than info.max_depth"},
    {"probe_leaf_link",
     "probe <-> leaf links are one-to-one and the probe's node field links back (-1 for grid probes)"},
    {"probe_depth_mismatch", "a probe's depth equals its node's depth (0 for grid probes)"},
    {"probe_outside_node", "a probe lies inside its node's cube (relative epsilon)"},
    {"probe_values", "hit and back-face fractions in [0, 1], padding zero"},
    {"batch_link", "surfel chain links point at allocated batches in range"},
    {"batch_chain_endless", "a surfel chain ends (no loop)"},
    {"batch_shared", "no batch is in two chains"},
    {"batch_owner", "a batch's probe field and its chain end's link name the owning probe"},
    {"batch_count", "a batch holds 1..SURFELS_PER_BATCH surfels"},
    {"batch_orphan", "every allocated batch is in its owner's chain"},
    {"batch_lattice", "a batch's lattice range [first, first + count) lies inside [0, surfels_per_probe)"},
    {"surfel_values", "surfels in use: known flags, distance >= 0, unit normal on hits, colours >= 0, padding zero; "
                      "unused surfels zero"},
    {"probe_index_list", "the probe index list is the allocated probes ascending, then negative values"},
    {"leaf_queue_header", "pull origin in {0,1,2}, segment counts within capacity, padding zero"},
    {"leaf_entry_node",
     "leaf buffer entries in use name reachable nodes: parents in M0/M4, leaves in every other state"},
    {"leaf_entry_state", "leaf buffer entries in use hold a LEAF_* state"},
    {"leaf_entry_duplicate", "no node appears twice in one segment"},
    {"svo_index_range", "SVO child blocks, payload indices and probe slots are in range"},
    {"svo_tree", "SVO nodes form a tree: child blocks follow their parent, unshared, all non-empty nodes reachable"},
    {"svo_leaf_shared", "no SVO payload is used by two voxels"},
    {"svo_depth", "no SVO voxel is deeper than info.svo_depth"},
    {"svo_freed_probe", "SVO payloads name allocated probes only"},
    {"svo_weights", "SVO payloads: used slots first, at least one, weights >= 0 summing to 1, unused weights 0"},
    {"grid_lattice",
     "grid placement only: a header of the file's resolution (2..255), finite origin, spacing > 0; each "
     "allocated probe at exactly one point, cell bits only for cells inside the lattice, reach bits 30-31 zero; "
     "points without probe: all zero"},
    {"sky", "beside the lighting sections only: a header of width 4..1024 and height 2..512 and its RGB texels, finite "
            "and >= 0; an environment without sun; a physical sky's turbidity in [1.7, 10], a unit sun direction and a "
            "directional sun light or none (-1)"},
    {"cell_order", "cell records are sorted by strictly increasing cell index"},
    {"cell_bounds", "a cell's index is in the grid and its bounds are the grid cell's"},
    {"cell_root_node", "a cell's root node is the octree node covering exactly the cell, or -1"},
    {"cell_range", "cell ranges lie inside their sections, ascend without overlap, bytes = elements x size"},
    {"cell_membership", "each allocated element is in the range of its own cell; free elements in none"},
    {"cell_tracing", "one cell_tracing record per cell; its ranges cover the static tree's faces, nodes and vertices "
                     "without gaps, dynamic faces use no cell's vertex, and each cell's trace nodes, faces and "
                     "vertices refer only to each other, its faces' centroids inside it"},
    {"cell_checksum", "one checksum per cell; each equals the XXH3-64 of its cell's byte ranges, checked cell by cell"},
    {"cell_global_checksum", "with cell_tracing, one checksum per cell-split section; each equals the XXH3-64 of the "
                             "section's bytes outside every cell's range"},
    {"lighting_sections", "lighting sections present iff lighting_info is; its counts equal the sections; rays >= 1; "
                          "placement_rays = surfels_per_probe"},
    {"lighting_values", "unit directions and normals, colours >= 0, light types and unused fields, shadow offset > 0, "
                        "padding zero; 1.4 faces: indices in range, non-zero area"},
    {"lighting_flags", "trace triangle and emitter patch flags set no bit but bit 0 (double-sided)"},
    {"bvh_tree", "BVH: children after their node, each node reached once, leaves of 1..4 triangles covering each once, "
                 "depth, boxes"},
    {"trace_tree",
     "1.4 trees: roots and children in their tree's nodes and after their node, each node reached once, leaves of 1..8 "
     "faces covering each once, depth, every face inside every box above it as the GPU decodes it"},
    {"dynamic_ranges",
     "dynamic objects' node and triangle ranges contiguous after the static ones, each tree inside its ranges"},
    {"dynamic_values", "dynamic objects: finite boxes holding their triangles, rest poses finite with determinant > 0"},
};

} // namespace

std::span<const InvariantInfo> invariants() { return kInvariants; }

ValidationReport validate(const ProbeVolume& volume, const ValidateOptions& options) {
  return validate(volume, tracing_view(volume), options);
}

ValidationReport validate(const ProbeVolume& volume, const TracingView& tracing, const ValidateOptions& options) {
  ValidationReport report;
  report.name = "volume";
  detail::Reporter out(report, options);
  run_phases(volume, tracing, nullptr, out);
  return report;
}

ValidationReport validate_without_cells(const ProbeVolume& volume, const TracingView& tracing,
                                        std::vector<CellEntry>& entries, const ValidateOptions& options) {
  ValidationReport report;
  report.name = "volume";
  detail::Reporter out(report, options);
  entries.assign(volume.cell_tracing.size(), CellEntry{});
  if (volume.cell_tracing.empty() || volume.cell_tracing.size() != volume.cells.size()) {
    out.add("cell_tracing", "cell_tracing", -1, "a check without the cells needs one cell_tracing record per cell");
    return report;
  }
  const detail::DeferredCells deferred{entries};
  run_phases(volume, tracing, &deferred, out);
  return report;
}

ValidationReport validate_cell_tracing(const ProbeVolume& volume, std::span<const CellEntry> entries, std::size_t k,
                                       const TracingView& cell, const ValidateOptions& options) {
  ValidationReport report;
  report.name = "cell_tracing[" + std::to_string(k) + "]";
  detail::Reporter out(report, options);
  if (k >= volume.cell_tracing.size() || k >= volume.cells.size() || entries.size() != volume.cell_tracing.size())
    throw Error(ErrorKind::internal,
                "validate_cell_tracing: no cell record " + std::to_string(k) + " or no entries for it");
  const CellTracing& r = volume.cell_tracing[k];
  if (cell.nodes.size() != r.trace_nodes.count || cell.faces.size() != r.trace_faces.count ||
      cell.vertices.size() != r.trace_vertices.count)
    throw Error(ErrorKind::internal, "validate_cell_tracing: the cell's elements are not its records' ranges");
  const detail::TracingWindow window{cell, r.trace_nodes.first, r.trace_faces.first, r.trace_vertices.first};
  try {
    detail::check_cell_self_contained(volume, k, window, out);
    if (out.count() == 0)
      detail::check_cell_trace_mesh(volume, entries[k], k, window, out); // indexes what the first checked
  } catch (const detail::StopValidation&) {
  }
  return report;
}

ValidationReport validate_file(std::span<const std::uint8_t> bytes, std::string_view name,
                               const ValidateOptions& options) {
  ValidationReport report;
  report.name = std::string(name);
  detail::Reporter out(report, options);
  ProbeVolume volume;
  TracingView tracing;
  std::vector<std::pair<std::string, std::string>> checksums; // section, message
  try {
    // Checksum mismatches are collected, not reported, until the file has decoded: whether it is readable
    // at all (exit 2 against 1) must not depend on --max-errors.
    const ContainerView container =
        parse_container(bytes, name, [&](const std::string& section, long long, const std::string& message) {
          checksums.emplace_back(section, message);
        });
    // The trace nodes, faces and vertices are checked where they lie in `bytes`, not copied: in a file's
    // mapping (probebake validate) the world is then the kernel's pages, not the process's memory. Bytes not
    // aligned for that (a caller's buffer) are decoded whole.
    const bool in_place = reinterpret_cast<std::uintptr_t>(bytes.data()) % kSectionAlignment == 0;
    volume = decode_probes(container, name, in_place ? TraceSections::leave_in_bytes : TraceSections::decode);
    tracing = in_place ? tracing_in(container, name) : tracing_view(volume);
    for (const auto& [section, message] : checksums) out.add("checksum", section, -1, message); // whole section
    detail::check_container(container, volume, out);
  } catch (const detail::StopValidation&) {
    return report;
  } catch (const Error& error) {
    report.readable = false;
    report.violations.push_back(Violation{"container", "container", -1, error.what()});
    return report;
  }
  run_phases(volume, tracing, nullptr, out);
  try {
    detail::check_cell_checksums(volume, tracing, out); // the file's bytes: a volume edited in memory is not checked
    detail::check_cell_global_checksums(volume, tracing, out);
  } catch (const detail::StopValidation&) {
    // max_errors reached
  }
  return report;
}

std::string violation_place(const Violation& violation) {
  std::string place = violation.section;
  if (violation.index >= 0) {
    // Appended piecewise: GCC 12 at -O3 warns falsely (-Wrestrict) on "[" + std::string&&.
    place += '[';
    place += std::to_string(violation.index);
    place += ']';
  }
  return place;
}

std::string format_violation(const Violation& violation) {
  return violation_place(violation) + ": " + violation.invariant + ": " + violation.message;
}

nlohmann::json report_to_json(const ValidationReport& report) {
  nlohmann::json violations = nlohmann::json::array();
  for (const Violation& v : report.violations) {
    violations.push_back(
        {{"invariant", v.invariant}, {"section", v.section}, {"index", v.index}, {"message", v.message}});
  }
  return {{"file", report.name},
          {"valid", report.valid()},
          {"readable", report.readable},
          {"truncated", report.truncated},
          {"cells_checked", report.cells_checked},
          {"violation_count", report.violations.size()},
          {"violations", violations}};
}

} // namespace probebake::formats
