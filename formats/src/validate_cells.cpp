// Validator phase for the streaming cell index (cells.h, docs/FORMAT.md "Cells"): records sorted by cell,
// exact bounds and root nodes, ranges inside their sections and in ascending order, every allocated
// element inside the range of the cell it belongs to and no free element inside any range.
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
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
    problem = concat(cursor.section, " byte range ", range.byte_offset, "+", range.byte_size, " disagrees with the element range");
  }
  if (!problem.empty()) {
    out.add("cell_range", "cells", cell, problem);
    return false;
  }
  cursor.end = first + count;
  return true;
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
void check_membership(const char* section, const std::vector<int>& owners, const std::vector<int>& expected, Reporter& out) {
  for (std::size_t i = 0; i < owners.size(); ++i) {
    if (owners[i] == expected[i]) continue;
    const long long index = static_cast<long long>(i);
    if (expected[i] < 0) {
      out.add("cell_membership", section, index, concat("free or unused element inside the range of cell ", owners[i]));
    } else if (owners[i] < 0) {
      out.add("cell_membership", section, index, concat("belongs to cell ", expected[i], " but is in no cell's range"));
    } else {
      out.add("cell_membership", section, index, concat("belongs to cell ", expected[i], " but is in the range of cell ", owners[i]));
    }
  }
}

void check_records(const ProbeVolume& volume, const OctreeFacts& octree, bool& ranges_ok, Reporter& out) {
  const int total = cells_per_axis(volume.cell_depth) * cells_per_axis(volume.cell_depth) * cells_per_axis(volume.cell_depth);
  RangeCursor probes{"probes", volume.probes.size(), sizeof(gpu::Probe)};
  RangeCursor batches{"surfel_batches", volume.surfel_batches.size(), sizeof(gpu::SurfelBatch)};
  RangeCursor leaves{"svo_leaves", volume.svo_leaves.size(), sizeof(gpu::SvoLeaf)};
  int previous = -1;
  for (std::size_t k = 0; k < volume.cells.size(); ++k) {
    const Cell& cell = volume.cells[k];
    const long long index = static_cast<long long>(k);
    ranges_ok = check_range(cell.probes, probes, index, out) && ranges_ok;
    ranges_ok = check_range(cell.surfel_batches, batches, index, out) && ranges_ok;
    ranges_ok = check_range(cell.svo_leaves, leaves, index, out) && ranges_ok;
    if (cell.cell_index < 0 || cell.cell_index >= total) {
      ranges_ok = false;
      out.add("cell_bounds", "cells", index, concat("cell index ", cell.cell_index, " outside [0, ", total, ")"));
      continue;
    }
    if (cell.cell_index <= previous) out.add("cell_order", "cells", index, concat("cell index ", cell.cell_index, " does not increase"));
    previous = cell.cell_index;
    glm::vec3 min, max;
    cell_bounds(volume.info, volume.cell_depth, cell.cell_index, min, max);
    if (cell.bounds_min != min || cell.bounds_max != max) out.add("cell_bounds", "cells", index, "bounds differ from the cell grid");
    if (octree.clean && cell.root_node != cell_root_node(volume, volume.cell_depth, cell.cell_index)) {
      out.add("cell_root_node", "cells", index, concat("root node ", cell.root_node, " is not the node covering the cell"));
    }
  }
}

std::vector<int> expected_probe_cells(const ProbeVolume& volume) {
  std::vector<int> expected(volume.probes.size(), -1);
  for (std::size_t i = 0; i < volume.probes.size(); ++i) {
    if (volume.probes[i].link != 0) expected[i] = cell_of_point(volume.info, volume.cell_depth, volume.probes[i].position);
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

} // namespace

void check_cells(const ProbeVolume& volume, const OctreeFacts& octree, Reporter& out) {
  if (volume.cells.empty() || volume.cell_depth < 0 || volume.cell_depth > kMaxCellDepth) return;
  bool ranges_ok = true;
  check_records(volume, octree, ranges_ok, out);
  if (!ranges_ok) return;
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
  check_membership("svo_leaves", range_owners(volume.cells, volume.svo_leaves.size(), &Cell::svo_leaves), leaf_cells, out);
}

} // namespace probebake::formats::detail
