// Streaming cells (this project's addition to the octree thesis §3.1 buffers, see cells.h): cell
// geometry, element-to-cell membership and the writer-side reordering that makes each cell contiguous.
#include "probebake/formats/cells.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <span>
#include <string>

#include "probebake/formats/error.h"
#include "probebake/formats/grid_lattice.h"
#include "probebake/formats/octree.h"

// Header-only, as in container.cpp: the runtime links formats.
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace probebake::formats {
namespace {

constexpr int kNoCell = std::numeric_limits<int>::max(); // sorts after every cell
constexpr int kMaxSvoDepth = 30;                         // voxel coordinates must fit in an int

struct Voxel {
  int node;
  int depth;
  int x, y, z;
};

int voxel_cell(const Voxel& voxel, int cell_depth) {
  const int n = cells_per_axis(cell_depth);
  auto to_cell = [&](int coordinate) {
    return voxel.depth >= cell_depth ? coordinate >> (voxel.depth - cell_depth)
                                     : coordinate << (cell_depth - voxel.depth);
  };
  return to_cell(voxel.x) + n * (to_cell(voxel.y) + n * to_cell(voxel.z));
}

// Stable order of element indices by key; returns old index per new position.
std::vector<int> order_by_key(const std::vector<int>& key) {
  std::vector<int> order(key.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });
  return order;
}

std::vector<int> invert(const std::vector<int>& order) {
  std::vector<int> new_of_old(order.size());
  for (std::size_t position = 0; position < order.size(); ++position)
    new_of_old[order[position]] = static_cast<int>(position);
  return new_of_old;
}

template <typename T>
std::vector<T> permuted(const std::vector<T>& elements, const std::vector<int>& order) {
  std::vector<T> result;
  result.reserve(order.size());
  for (int old : order) result.push_back(elements[old]);
  return result;
}

std::vector<int> probe_cells(const ProbeVolume& volume, int cell_depth) {
  std::vector<int> cells(volume.probes.size(), kNoCell);
  for (std::size_t i = 0; i < volume.probes.size(); ++i) {
    if (volume.probes[i].link != 0) cells[i] = cell_of_point(volume.info, cell_depth, volume.probes[i].position);
  }
  return cells;
}

[[noreturn]] void throw_invalid(const std::string& what) {
  throw Error(ErrorKind::internal, "arrange_cells: " + what + " (validate the volume first)");
}

// Batch order: each probe's chain in chain order, probes in their new order, then unowned batches.
std::vector<int> batch_order(const ProbeVolume& volume, const std::vector<int>& probe_order,
                             std::vector<int>& batch_cell, const std::vector<int>& cell_of_probe) {
  const std::size_t count = volume.surfel_batches.size();
  std::vector<int> order;
  std::vector<bool> placed(count, false);
  batch_cell.assign(count, kNoCell);
  for (int probe : probe_order) {
    const int link = volume.probes[probe].link;
    if (link == 0 || ~link == gpu::PROBE_NO_SURFELS) continue;
    for (int batch = ~link;;) {
      if (batch < 0 || static_cast<std::size_t>(batch) >= count || placed[batch]) throw_invalid("broken surfel chain");
      placed[batch] = true;
      batch_cell[batch] = cell_of_probe[probe];
      order.push_back(batch);
      const int next = volume.surfel_batches[batch].link;
      if (next >= 0) break;
      batch = ~next;
    }
  }
  for (std::size_t batch = 0; batch < count; ++batch) {
    if (!placed[batch]) order.push_back(static_cast<int>(batch));
  }
  return order;
}

// Rewrites every index into the permuted sections (.at(): a link out of range is a caller bug).
void remap_links(ProbeVolume& volume, const std::vector<int>& new_probe, const std::vector<int>& new_batch,
                 const std::vector<int>& new_leaf) {
  for (std::size_t i = 0; i < volume.octree.size(); ++i) {
    if (is_node_index(static_cast<int>(i)) && volume.octree[i] < 0) volume.octree[i] = ~new_probe.at(~volume.octree[i]);
  }
  for (gpu::Probe& probe : volume.probes) {
    if (probe.link < 0 && ~probe.link != gpu::PROBE_NO_SURFELS) probe.link = ~new_batch.at(~probe.link);
  }
  for (gpu::SurfelBatch& batch : volume.surfel_batches) {
    if (batch.link == 0) continue;
    batch.link = batch.link < 0 ? ~new_batch.at(~batch.link) : new_probe.at(batch.link - 1) + 1;
    batch.probe = new_probe.at(batch.probe);
  }
  for (std::int32_t& node : volume.svo_nodes) {
    if (node < 0) node = ~new_leaf.at(~node);
  }
  for (gpu::SvoLeaf& leaf : volume.svo_leaves) {
    for (int slot = 0; slot < gpu::SVO_PROBES_PER_LEAF; ++slot) {
      if (leaf.probes[slot] >= 0) leaf.probes[slot] = new_probe.at(leaf.probes[slot]);
    }
  }
  remap_grid_probes(volume.grid_lattice, new_probe);
}

// Range of the elements with key == cell in a key vector sorted ascending.
CellRange range_of(const std::vector<int>& sorted_keys, int cell, std::size_t element_size) {
  const auto lower = std::lower_bound(sorted_keys.begin(), sorted_keys.end(), cell);
  const auto upper = std::upper_bound(lower, sorted_keys.end(), cell);
  CellRange range;
  range.first = static_cast<std::uint32_t>(lower - sorted_keys.begin());
  range.count = static_cast<std::uint32_t>(upper - lower);
  range.byte_offset = range.first * element_size;
  range.byte_size = range.count * element_size;
  return range;
}

} // namespace

int cell_of_point(const gpu::VolumeInfo& info, int cell_depth, glm::vec3 point) {
  const int n = cells_per_axis(cell_depth);
  int coordinate[3] = {0, 0, 0};
  for (int axis = 0; axis < 3; ++axis) {
    const float t = (point[axis] - info.root_min[axis]) / info.root_size * static_cast<float>(n);
    if (!(t >= 0.0f)) continue; // negative or NaN: first cell
    coordinate[axis] = t >= static_cast<float>(n) ? n - 1 : static_cast<int>(t);
  }
  return coordinate[0] + n * (coordinate[1] + n * coordinate[2]);
}

int cell_of_triangle(const gpu::VolumeInfo& info, int cell_depth, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  return cell_of_point(info, cell_depth, (a + b + c) / 3.0f);
}

void cell_bounds(const gpu::VolumeInfo& info, int cell_depth, int cell_index, glm::vec3& min, glm::vec3& max) {
  const int n = cells_per_axis(cell_depth);
  const float size = info.root_size / static_cast<float>(n);
  const glm::vec3 coordinate(static_cast<float>(cell_index % n), static_cast<float>((cell_index / n) % n),
                             static_cast<float>(cell_index / (n * n)));
  min = info.root_min + coordinate * size;
  max = min + glm::vec3(size);
}

int cell_root_node(const ProbeVolume& volume, int cell_depth, int cell_index) {
  const int n = cells_per_axis(cell_depth);
  const int x = cell_index % n, y = (cell_index / n) % n, z = cell_index / (n * n);
  int node = gpu::OCTREE_ROOT;
  for (int level = cell_depth - 1; level >= 0; --level) {
    const int meta = volume.octree.at(node);
    if (meta <= 0) return -1; // a leaf above the cell depth covers this cell
    if (!is_meta_index(meta) || static_cast<std::size_t>(meta) + 9 > volume.octree.size()) {
      throw Error(ErrorKind::input, "octree: node " + std::to_string(node) + " has a bad child index");
    }
    const int octant = ((x >> level) & 1) | (((y >> level) & 1) << 1) | (((z >> level) & 1) << 2);
    node = child_node(meta, octant);
  }
  return node;
}

std::vector<int> svo_leaf_cells(const ProbeVolume& volume, int cell_depth) {
  const std::vector<std::int32_t>& nodes = volume.svo_nodes;
  std::vector<int> cells(volume.svo_leaves.size(), -1);
  if (nodes.empty()) return cells;
  auto fail = [](const std::string& what) { throw Error(ErrorKind::input, "svo_nodes: " + what); };
  std::vector<Voxel> stack{Voxel{0, 0, 0, 0, 0}};
  while (!stack.empty()) {
    const Voxel voxel = stack.back();
    stack.pop_back();
    const int value = nodes[voxel.node];
    if (value < 0) {
      const int leaf = ~value;
      if (static_cast<std::size_t>(leaf) >= cells.size() || cells[leaf] != -1) fail("bad or shared leaf payload index");
      cells[leaf] = voxel_cell(voxel, cell_depth);
    } else if (value > 0) {
      // Children after their parent (tree-shaped buffers) also rules out cycles.
      if (value <= voxel.node || static_cast<std::size_t>(value) + 8 > nodes.size() || voxel.depth >= kMaxSvoDepth) {
        fail("node " + std::to_string(voxel.node) + " has a bad child index");
      }
      for (int octant = 7; octant >= 0; --octant) {
        stack.push_back(Voxel{value + octant, voxel.depth + 1, 2 * voxel.x + (octant & 1),
                              2 * voxel.y + ((octant >> 1) & 1), 2 * voxel.z + ((octant >> 2) & 1)});
      }
    }
  }
  return cells;
}

// The tracing ranges of the volume's cells by cell index; empty when its tracing is not split by cell, or
// split on another grid (the tree stays a valid tree, only its cell index is lost).
std::map<int, CellTracing> tracing_by_cell(const ProbeVolume& volume, int cell_depth) {
  std::map<int, CellTracing> tracing;
  if (volume.cell_tracing.empty() || volume.cell_depth != cell_depth) return tracing;
  if (volume.cell_tracing.size() != volume.cells.size()) throw_invalid("cell_tracing and cells differ in length");
  for (std::size_t k = 0; k < volume.cells.size(); ++k) tracing[volume.cells[k].cell_index] = volume.cell_tracing[k];
  return tracing;
}

// Ranges that continue where the previous cell's ended, for a cell without tracing data.
CellTracing empty_tracing(const CellTracing& previous) {
  CellTracing empty;
  for (auto member : {&CellTracing::trace_nodes, &CellTracing::trace_faces, &CellTracing::trace_vertices}) {
    const CellRange& before = previous.*member;
    CellRange& range = empty.*member;
    range.first = before.first + before.count;
    range.byte_offset = before.byte_offset + before.byte_size;
  }
  return empty;
}

void arrange_cells(ProbeVolume& volume, int cell_depth) {
  if (cell_depth < 0 || cell_depth > kMaxCellDepth) {
    throw Error(ErrorKind::usage,
                "cell depth " + std::to_string(cell_depth) + " outside [0, " + std::to_string(kMaxCellDepth) + "]");
  }
  const std::map<int, CellTracing> tracing = tracing_by_cell(volume, cell_depth);
  const std::vector<int> cell_of_probe = probe_cells(volume, cell_depth);
  const std::vector<int> probe_order = order_by_key(cell_of_probe);
  std::vector<int> cell_of_batch;
  const std::vector<int> batches_in_order = batch_order(volume, probe_order, cell_of_batch, cell_of_probe);
  std::vector<int> cell_of_leaf = svo_leaf_cells(volume, cell_depth);
  for (int& cell : cell_of_leaf) cell = cell < 0 ? kNoCell : cell;
  const std::vector<int> leaf_order = order_by_key(cell_of_leaf);

  remap_links(volume, invert(probe_order), invert(batches_in_order), invert(leaf_order));
  volume.probes = permuted(volume.probes, probe_order);
  volume.surfel_batches = permuted(volume.surfel_batches, batches_in_order);
  volume.svo_leaves = permuted(volume.svo_leaves, leaf_order);
  rebuild_probe_index(volume);

  const std::vector<int> probe_keys = permuted(cell_of_probe, probe_order);
  const std::vector<int> batch_keys = permuted(cell_of_batch, batches_in_order);
  const std::vector<int> leaf_keys = permuted(cell_of_leaf, leaf_order);
  std::vector<int> used_cells;
  for (const auto& [cell, ranges] : tracing) used_cells.push_back(cell);
  for (const std::vector<int>* keys : {&probe_keys, &batch_keys, &leaf_keys}) {
    for (int cell : *keys) {
      if (cell != kNoCell) used_cells.push_back(cell);
    }
  }
  std::sort(used_cells.begin(), used_cells.end());
  used_cells.erase(std::unique(used_cells.begin(), used_cells.end()), used_cells.end());

  volume.cell_depth = cell_depth;
  volume.cells.clear();
  volume.cell_tracing.clear();
  CellTracing previous_tracing;
  for (int index : used_cells) {
    if (!tracing.empty()) {
      const auto found = tracing.find(index);
      previous_tracing = found != tracing.end() ? found->second : empty_tracing(previous_tracing);
      volume.cell_tracing.push_back(previous_tracing);
    }
    Cell cell;
    cell.cell_index = index;
    cell_bounds(volume.info, cell_depth, index, cell.bounds_min, cell.bounds_max);
    cell.root_node = cell_root_node(volume, cell_depth, index);
    cell.probes = range_of(probe_keys, index, sizeof(gpu::Probe));
    cell.surfel_batches = range_of(batch_keys, index, sizeof(gpu::SurfelBatch));
    cell.svo_leaves = range_of(leaf_keys, index, sizeof(gpu::SvoLeaf));
    volume.cells.push_back(cell);
  }
  volume.cell_checksums.clear(); // a file's, for other ranges; the writer takes the bytes' own (cell_checksums_of)
  volume.cell_global_checksums.clear();
}

std::uint64_t cell_bytes(const ProbeVolume& volume, std::size_t k) {
  const Cell& cell = volume.cells.at(k);
  std::uint64_t bytes = cell.probes.byte_size + cell.surfel_batches.byte_size + cell.svo_leaves.byte_size;
  if (k < volume.cell_tracing.size()) bytes += cell_tracing_bytes(volume.cell_tracing[k]);
  return bytes;
}

namespace {

template <class T>
void hash_range(XXH3_state_t& state, std::span<const T> section, const CellRange& range) {
  if (std::uint64_t(range.first) + range.count > section.size())
    throw Error(ErrorKind::internal, "cell_checksum: a range outside its section");
  if (range.count > 0) XXH3_64bits_update(&state, section.data() + range.first, std::size_t(range.count) * sizeof(T));
}

} // namespace

std::uint64_t cell_checksum(const ProbeVolume& volume, std::size_t k) {
  return cell_checksum(volume, tracing_view(volume), k);
}

std::uint64_t cell_checksum(const ProbeVolume& volume, const TracingView& tracing, std::size_t k) {
  const Cell& cell = volume.cells.at(k);
  XXH3_state_t state;
  XXH3_64bits_reset(&state);
  hash_range(state, std::span<const gpu::Probe>(volume.probes), cell.probes);
  hash_range(state, std::span<const gpu::SurfelBatch>(volume.surfel_batches), cell.surfel_batches);
  hash_range(state, std::span<const gpu::SvoLeaf>(volume.svo_leaves), cell.svo_leaves);
  if (k < volume.cell_tracing.size()) {
    const CellTracing& t = volume.cell_tracing[k];
    hash_range(state, tracing.nodes, t.trace_nodes);
    hash_range(state, tracing.faces, t.trace_faces);
    hash_range(state, tracing.vertices, t.trace_vertices);
  }
  return XXH3_64bits_digest(&state);
}

std::vector<std::uint64_t> cell_checksums_of(const ProbeVolume& volume) {
  std::vector<std::uint64_t> sums;
  if (!volume.cell_tracing.empty()) // files that stream (split tracing): the others keep the bytes of their version
    for (std::size_t k = 0; k < volume.cells.size(); ++k) sums.push_back(cell_checksum(volume, k));
  return sums;
}

namespace {

// The bytes of `section` between and after the ranges (ascending, inside it).
template <class T, class Record>
std::uint64_t global_checksum(std::span<const T> section, const std::vector<Record>& records,
                              CellRange Record::*member) {
  XXH3_state_t state;
  XXH3_64bits_reset(&state);
  std::uint64_t cursor = 0;
  const auto hash_to = [&](std::uint64_t end) {
    if (end < cursor || end > section.size())
      throw Error(ErrorKind::internal, "cell_global_checksums: the cells' ranges do not ascend inside their section");
    if (end > cursor) XXH3_64bits_update(&state, section.data() + cursor, std::size_t(end - cursor) * sizeof(T));
    cursor = end;
  };
  for (const Record& record : records) {
    const CellRange& range = record.*member;
    hash_to(range.first);
    cursor = std::uint64_t(range.first) + range.count;
  }
  hash_to(section.size());
  return XXH3_64bits_digest(&state);
}

} // namespace

std::vector<std::uint64_t> cell_global_checksums_of(const ProbeVolume& volume, const TracingView& tracing) {
  if (volume.cell_tracing.empty()) return {};
  return {
      global_checksum(std::span<const gpu::Probe>(volume.probes), volume.cells, &Cell::probes),
      global_checksum(std::span<const gpu::SurfelBatch>(volume.surfel_batches), volume.cells, &Cell::surfel_batches),
      global_checksum(std::span<const gpu::SvoLeaf>(volume.svo_leaves), volume.cells, &Cell::svo_leaves),
      global_checksum(tracing.nodes, volume.cell_tracing, &CellTracing::trace_nodes),
      global_checksum(tracing.faces, volume.cell_tracing, &CellTracing::trace_faces),
      global_checksum(tracing.vertices, volume.cell_tracing, &CellTracing::trace_vertices)};
}

void clear_cells(ProbeVolume& volume) {
  volume.cells.clear();
  volume.cell_tracing.clear();
  volume.cell_checksums.clear();
  volume.cell_global_checksums.clear();
  volume.cell_depth = 0;
}

} // namespace probebake::formats
