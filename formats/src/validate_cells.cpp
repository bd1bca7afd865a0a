// Validator phase for the streaming cell index (cells.h, docs/FORMAT.md "Cells"): records sorted by cell,
// exact bounds and root nodes, ranges inside their sections and in ascending order, every allocated
// element inside the range of the cell it belongs to and no free element inside any range, each cell's
// tracing self-contained; for files, each cell's bytes equal to its checksum.
#include <initializer_list>
#include <utility>

#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/trace_mesh.h"
#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

struct RangeCursor {
  const char* section;
  std::size_t element_count;
  std::size_t element_size;
  std::uint64_t end = 0; // end of the previous cell's range
};

bool check_range(const CellRange& range, RangeCursor& cursor, long long cell, Reporter& out) {
  const std::uint64_t first = range.first, count = range.count;
  std::string problem;
  if (first + count > cursor.element_count) {
    problem = concat(cursor.section, " range ", first, "+", count, " exceeds ", cursor.element_count, " elements");
  } else if (first < cursor.end) {
    problem = concat(cursor.section, " range starts at ", first, ", before the previous cell's end ", cursor.end);
  } else if (range.byte_offset != first * cursor.element_size || range.byte_size != count * cursor.element_size) {
    problem = concat(cursor.section, " byte range ", range.byte_offset, "+", range.byte_size,
                     " disagrees with the element range");
  }
  if (!problem.empty()) {
    out.add("cell_range", "cells", cell, problem);
    return false;
  }
  cursor.end = first + count;
  return true;
}

// A record's ranges into several sections, each checked (and reported) against its section's cursor in turn.
bool check_ranges(std::initializer_list<std::pair<const CellRange&, RangeCursor&>> ranges, long long cell,
                  Reporter& out) {
  bool ok = true;
  for (const auto& [range, cursor] : ranges) ok = check_range(range, cursor, cell, out) && ok;
  return ok;
}

// Owning cell of each element according to the ranges (-1: in no range).
std::vector<int> range_owners(const std::vector<Cell>& cells, std::size_t count, CellRange Cell::*member) {
  std::vector<int> owners(count, -1);
  for (const Cell& cell : cells) {
    const CellRange& range = cell.*member;
    for (std::uint32_t i = 0; i < range.count; ++i) owners[range.first + i] = cell.cell_index;
  }
  return owners;
}

// `expected` is the cell an element belongs to, -1 for an element that belongs to no cell (free).
void check_membership(const char* section, const std::vector<int>& owners, const std::vector<int>& expected,
                      Reporter& out) {
  for (std::size_t i = 0; i < owners.size(); ++i) {
    if (owners[i] == expected[i]) continue;
    const long long index = static_cast<long long>(i);
    if (expected[i] < 0) {
      out.add("cell_membership", section, index, concat("free or unused element inside the range of cell ", owners[i]));
    } else if (owners[i] < 0) {
      out.add("cell_membership", section, index, concat("belongs to cell ", expected[i], " but is in no cell's range"));
    } else {
      out.add("cell_membership", section, index,
              concat("belongs to cell ", expected[i], " but is in the range of cell ", owners[i]));
    }
  }
}

void check_records(const ProbeVolume& volume, const OctreeFacts& octree, bool& ranges_ok, Reporter& out) {
  const int total = cell_count(volume.cell_depth);
  RangeCursor probes{"probes", volume.probes.size(), sizeof(gpu::Probe)};
  RangeCursor batches{"surfel_batches", volume.surfel_batches.size(), sizeof(gpu::SurfelBatch)};
  RangeCursor leaves{"svo_leaves", volume.svo_leaves.size(), sizeof(gpu::SvoLeaf)};
  int previous = -1;
  for (std::size_t k = 0; k < volume.cells.size(); ++k) {
    const Cell& cell = volume.cells[k];
    const long long index = static_cast<long long>(k);
    if (!check_ranges({{cell.probes, probes}, {cell.surfel_batches, batches}, {cell.svo_leaves, leaves}}, index, out))
      ranges_ok = false;
    if (cell.cell_index < 0 || cell.cell_index >= total) {
      ranges_ok = false;
      out.add("cell_bounds", "cells", index, concat("cell index ", cell.cell_index, " outside [0, ", total, ")"));
      continue;
    }
    if (cell.cell_index <= previous)
      out.add("cell_order", "cells", index, concat("cell index ", cell.cell_index, " does not increase"));
    previous = cell.cell_index;
    glm::vec3 min, max;
    cell_bounds(volume.info, volume.cell_depth, cell.cell_index, min, max);
    if (cell.bounds_min != min || cell.bounds_max != max)
      out.add("cell_bounds", "cells", index, "bounds differ from the cell grid");
    if (octree.clean && cell.root_node != cell_root_node(volume, volume.cell_depth, cell.cell_index)) {
      out.add("cell_root_node", "cells", index,
              concat("root node ", cell.root_node, " is not the node covering the cell"));
    }
  }
}

std::vector<int> expected_probe_cells(const ProbeVolume& volume) {
  std::vector<int> expected(volume.probes.size(), -1);
  for (std::size_t i = 0; i < volume.probes.size(); ++i) {
    if (volume.probes[i].link != 0)
      expected[i] = cell_of_point(volume.info, volume.cell_depth, volume.probes[i].position);
  }
  return expected;
}

std::vector<int> expected_batch_cells(const ProbeVolume& volume, const std::vector<int>& probe_cells) {
  std::vector<int> expected(volume.surfel_batches.size(), -1);
  for (std::size_t b = 0; b < volume.surfel_batches.size(); ++b) {
    const gpu::SurfelBatch& batch = volume.surfel_batches[b];
    if (batch.link != 0 && batch.probe >= 0 && static_cast<std::size_t>(batch.probe) < probe_cells.size()) {
      expected[b] = probe_cells[batch.probe];
    }
  }
  return expected;
}

// The static tree's faces: those before the first dynamic object's (format 1.3 objects follow tree 0).
std::size_t static_faces(const ProbeVolume& volume, const TracingView& tracing) {
  if (volume.dynamic_objects.empty()) return tracing.faces.size();
  return std::min<std::size_t>(tracing.faces.size(),
                               std::size_t(std::max(0, volume.dynamic_objects[0].first_triangle)));
}

bool in_range(std::uint64_t index, const CellRange& range) {
  return index >= range.first && index < std::uint64_t(range.first) + range.count;
}

// The first way cell k's part of the static tree reaches outside its own nodes, faces and vertices, or a
// face whose centroid lies in another cell; empty when it is self-contained. `w` holds the cell's ranges.
std::string tracing_leak(const ProbeVolume& volume, const TracingWindow& w, const Cell& cell,
                         const CellTracing& ranges) {
  for (std::uint32_t n = ranges.trace_nodes.first; n < ranges.trace_nodes.first + ranges.trace_nodes.count; ++n) {
    for (const std::uint32_t word : w.node(n).child) {
      if (is_leaf_word(word)) {
        if (!in_range(leaf_first(word), ranges.trace_faces) ||
            !in_range(leaf_first(word) + leaf_count(word) - 1, ranges.trace_faces))
          return concat("trace node ", n, " has faces outside the cell's");
      } else if (!in_range(word, ranges.trace_nodes) || word <= n) {
        return concat("trace node ", n, " has child ", word, " outside the cell's nodes after it");
      }
    }
  }
  const gpu::VolumeInfo& info = volume.info;
  for (std::uint32_t f = ranges.trace_faces.first; f < ranges.trace_faces.first + ranges.trace_faces.count; ++f) {
    const gpu::TraceFace& face = w.face(f);
    glm::vec3 corners[3];
    for (int k = 0; k < 3; ++k) {
      if (!in_range(face.vertex[k], ranges.trace_vertices))
        return concat("trace face ", f, " uses vertex ", face.vertex[k], " outside the cell's");
      const gpu::TraceVertex& v = w.vertex(face.vertex[k]);
      corners[k] = glm::vec3(v.x, v.y, v.z);
    }
    const int owner = cell_of_triangle(info, volume.cell_depth, corners[0], corners[1], corners[2]);
    if (owner != cell.cell_index) return concat("trace face ", f, " has its centroid in cell ", owner);
  }
  return {};
}

// What a reader that streams relies on (docs/FORMAT.md section 6.1): the cells' non-empty node ranges follow
// one another without a gap up to the static tree's last node (the top level before them), their vertex
// ranges likewise from vertex 0, and the faces outside the cells (the dynamic objects') use only vertices
// after the cells'. The empty string when it holds.
std::string layout_problem(const ProbeVolume& volume, const TracingView& tracing, std::uint64_t static_faces) {
  std::uint64_t node_end = 0, vertex_end = 0;
  bool any_nodes = false;
  for (std::size_t k = 0; k < volume.cell_tracing.size(); ++k) {
    const CellTracing& r = volume.cell_tracing[k];
    if (r.trace_nodes.count > 0) {
      if (any_nodes && r.trace_nodes.first != node_end)
        return concat("cell record ", k, "'s nodes start at ", r.trace_nodes.first, ", not at ", node_end,
                      " where the previous cell's end");
      any_nodes = true, node_end = std::uint64_t(r.trace_nodes.first) + r.trace_nodes.count;
    }
    if (r.trace_vertices.count > 0) {
      if (r.trace_vertices.first != vertex_end)
        return concat("cell record ", k, "'s vertices start at ", r.trace_vertices.first, ", not at ", vertex_end);
      vertex_end = std::uint64_t(r.trace_vertices.first) + r.trace_vertices.count;
    }
  }
  const std::uint64_t static_nodes =
      volume.trace_trees.empty() ? 0 : std::uint64_t(std::max(0, volume.trace_trees[0].node_count));
  if (any_nodes && node_end != static_nodes)
    return concat("the cells' nodes end at ", node_end, ", the static tree's at ", static_nodes);
  for (std::uint64_t f = static_faces; f < tracing.faces.size(); ++f)
    for (std::uint32_t k : tracing.faces[f].vertex)
      if (k < vertex_end) return concat("trace face ", f, " of the dynamic objects uses vertex ", k, " of a cell");
  return {};
}

// cell_tracing: one record per cell, ranges inside their sections and ascending, the static tree's faces
// all in some cell's range, the layout above, and (unless the cells are left for later) each cell's nodes,
// faces and vertices referring only to each other.
void check_cell_tracing(const ProbeVolume& volume, const TracingView& tracing, const DeferredCells* deferred,
                        Reporter& out) {
  if (volume.cell_tracing.empty()) return;
  if (volume.cell_tracing.size() != volume.cells.size()) {
    out.add("cell_tracing", "cell_tracing", -1,
            concat(volume.cell_tracing.size(), " records for ", volume.cells.size(), " cells"));
    return;
  }
  RangeCursor nodes{"trace_nodes", tracing.nodes.size(), sizeof(gpu::TraceNode)};
  RangeCursor faces{"trace_faces", tracing.faces.size(), sizeof(gpu::TraceFace)};
  RangeCursor vertices{"trace_vertices", tracing.vertices.size(), sizeof(gpu::TraceVertex)};
  bool ranges_ok = true;
  std::uint64_t covered_faces = 0;
  for (std::size_t k = 0; k < volume.cell_tracing.size(); ++k) {
    const CellTracing& ranges = volume.cell_tracing[k];
    const long long index = static_cast<long long>(k);
    if (!check_ranges({{ranges.trace_nodes, nodes}, {ranges.trace_faces, faces}, {ranges.trace_vertices, vertices}},
                      index, out))
      ranges_ok = false;
    covered_faces += ranges.trace_faces.count;
  }
  if (!ranges_ok) return;
  const std::size_t first_face = volume.cell_tracing.front().trace_faces.first;
  if (first_face != 0 || covered_faces != static_faces(volume, tracing) || faces.end != covered_faces)
    out.add("cell_tracing", "cell_tracing", -1,
            concat("the cells' faces are ", first_face, "+", covered_faces, ", the static tree's 0+",
                   static_faces(volume, tracing)));
  if (const std::string problem = layout_problem(volume, tracing, covered_faces); !problem.empty())
    out.add("cell_tracing", "cell_tracing", -1, problem);
  if (deferred) return;
  for (std::size_t k = 0; k < volume.cell_tracing.size(); ++k) {
    const std::string leak = tracing_leak(volume, TracingWindow{tracing}, volume.cells[k], volume.cell_tracing[k]);
    if (!leak.empty()) out.add("cell_tracing", "cell_tracing", static_cast<long long>(k), leak);
  }
}

} // namespace

// cell_checksums (1.6): one per cell, each the checksum of the cell's bytes in the file (cells.h
// cell_checksum), so that a reader that loads one cell can trust it. Each cell is checked on its own and a
// damaged one is named; a cell whose ranges leave their sections is cell_range's.
void check_cell_checksums(const ProbeVolume& volume, const TracingView& tracing, Reporter& out) {
  if (volume.cell_checksums.empty()) return;
  if (volume.cell_checksums.size() != volume.cells.size()) {
    out.add("cell_checksum", "cell_checksums", -1,
            concat(volume.cell_checksums.size(), " checksums for ", volume.cells.size(), " cells"));
    return;
  }
  out.cells_checked(volume.cells.size());
  for (std::size_t k = 0; k < volume.cells.size(); ++k) {
    std::uint64_t sum = 0;
    try {
      sum = cell_checksum(volume, tracing, k);
    } catch (const Error&) {
      continue;
    }
    if (sum == volume.cell_checksums[k]) continue;
    out.add("cell_checksum", "cells", static_cast<long long>(k),
            concat("the ", cell_bytes(volume, k), " bytes of cell ", volume.cells[k].cell_index,
                   " differ from its checksum"));
  }
}

// cell_global_checksums (1.7): with cell_tracing, one per cell-split section, each the checksum of the bytes
// outside every cell's range (cells.h), which a streaming load reads alone.
void check_cell_global_checksums(const ProbeVolume& volume, const TracingView& tracing, Reporter& out) {
  const std::vector<std::uint64_t>& stored = volume.cell_global_checksums;
  if (stored.empty()) return;
  if (volume.cell_tracing.empty())
    return out.add("cell_global_checksum", "cell_global_checksums", -1, "a file without cell_tracing");
  if (stored.size() != std::size(kCellSplitSections))
    return out.add("cell_global_checksum", "cell_global_checksums", -1,
                   concat(stored.size(), " checksums, expected ", std::size(kCellSplitSections)));
  std::vector<std::uint64_t> computed;
  try {
    computed = cell_global_checksums_of(volume, tracing);
  } catch (const Error&) {
    return; // ranges outside their sections or out of order: cell_range's and cell_tracing's
  }
  for (std::size_t s = 0; s < computed.size(); ++s)
    if (computed[s] != stored[s])
      out.add("cell_global_checksum", "cell_global_checksums", static_cast<long long>(s),
              concat("the bytes of ", section_name(static_cast<std::uint32_t>(kCellSplitSections[s])),
                     " outside the cells differ from their checksum"));
}

void check_cell_self_contained(const ProbeVolume& volume, std::size_t k, const TracingWindow& cell, Reporter& out) {
  const std::string leak = tracing_leak(volume, cell, volume.cells[k], volume.cell_tracing[k]);
  if (!leak.empty()) out.add("cell_tracing", "cell_tracing", static_cast<long long>(k), leak);
}

void check_cells(const ProbeVolume& volume, const TracingView& tracing, const OctreeFacts& octree,
                 const DeferredCells* deferred, Reporter& out) {
  if (volume.cells.empty() && !volume.cell_tracing.empty())
    out.add("cell_tracing", "cell_tracing", -1, concat(volume.cell_tracing.size(), " records without cells"));
  if (volume.cells.empty() || volume.cell_depth < 0 || volume.cell_depth > kMaxCellDepth) return;
  bool ranges_ok = true;
  check_records(volume, octree, ranges_ok, out);
  if (!ranges_ok) return;
  check_cell_tracing(volume, tracing, deferred, out);
  const std::vector<int> probe_cells = expected_probe_cells(volume);
  check_membership("probes", range_owners(volume.cells, volume.probes.size(), &Cell::probes), probe_cells, out);
  check_membership("surfel_batches", range_owners(volume.cells, volume.surfel_batches.size(), &Cell::surfel_batches),
                   expected_batch_cells(volume, probe_cells), out);
  std::vector<int> leaf_cells;
  try {
    leaf_cells = svo_leaf_cells(volume, volume.cell_depth);
  } catch (const Error&) {
    return; // the SVO is not a tree; check_svo reported why
  }
  check_membership("svo_leaves", range_owners(volume.cells, volume.svo_leaves.size(), &Cell::svo_leaves), leaf_cells,
                   out);
}

} // namespace probebake::formats::detail
