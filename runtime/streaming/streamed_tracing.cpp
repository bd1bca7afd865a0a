// The static tracing tree streamed by cell (streamed_tracing.h): the arena's global region, each cell's block
// renumbered into it, drops, loads, compaction and the read-back check. The arena's size classes and block
// allocator are in streamed_tracing_blocks.cpp.
#include "streaming/streamed_tracing.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <optional>
#include <unordered_map>

#include "core/commands.h"
#include "core/error.h"
#include "streaming/stream_bindings.h"
#include "probebake/formats/error.h"
#include "probebake/formats/trace_mesh.h"
#include "probebake/runtime_types.h"

namespace probebake::runtime::detail {
namespace {

constexpr std::uint64_t kBlockUnit = 96; // a multiple of the node (32), face (16) and vertex (12) strides
constexpr std::uint64_t kNodeBytes = sizeof(gpu::TraceNode), kFaceBytes = sizeof(gpu::TraceFace), kVertexBytes = 12;
static_assert(kNodeBytes == 32 && kFaceBytes == 16 && sizeof(gpu::TraceVertex) == kVertexBytes);

std::uint64_t round_up(std::uint64_t x, std::uint64_t to) { return (x + to - 1) / to * to; }

std::uint32_t leaf_word(std::uint32_t first, std::uint32_t count) {
  return gpu::TRACE_CHILD_LEAF | ((count - 1u) << gpu::TRACE_LEAF_COUNT_SHIFT) | first;
}

// A child word renumbered from one place to another (inner nodes by node index, leaves by face index).
std::uint32_t moved_word(std::uint32_t word, std::int64_t node_shift, std::int64_t face_shift) {
  if (formats::is_leaf_word(word))
    return (word & ~gpu::TRACE_LEAF_FIRST_MASK) | std::uint32_t(std::int64_t(formats::leaf_first(word)) + face_shift);
  return std::uint32_t(std::int64_t(word) + node_shift);
}

} // namespace

// Where a block's parts lie: byte offsets from the block start, and the block's size.
struct StreamedTracing::Layout {
  std::uint64_t faces_at = 0, vertices_at = 0, bytes = 0;
  Layout(std::uint64_t nodes, std::uint64_t faces, std::uint64_t vertices) {
    faces_at = nodes * kNodeBytes;
    vertices_at = round_up(faces_at + faces * kFaceBytes, kVertexBytes);
    bytes = round_up(vertices_at + vertices * kVertexBytes, kBlockUnit);
  }
};

std::uint64_t StreamedTracing::block_bytes(const formats::CellTracing& r) {
  return r.trace_faces.count > 0 ? Layout(r.trace_nodes.count, r.trace_faces.count, r.trace_vertices.count).bytes : 0;
}

StreamedTracing::StreamedTracing(Device& device, const formats::ProbeVolume& volume,
                                 const formats::TracingView& tracing, std::unique_ptr<CellSource> source,
                                 std::uint64_t cell_bytes, std::uint64_t staging_bytes, std::uint32_t rings,
                                 bool background)
    : device_(device), source_(std::move(source)), blocks_(cell_bytes, kBlockUnit) {
  if (volume.cell_tracing.empty() || volume.cell_tracing.size() != volume.cells.size())
    fail(StatusCode::unsupported, "streaming needs the static tracing tree split by cell (format 1.5 cell_tracing); "
                                  "bake with --cell-size or --cell-depth >= 1");
  if (background) reader_ = std::make_unique<BackgroundCellReader>(*source_);
  for (const formats::CellTracing& ranges : volume.cell_tracing) {
    CellPart cell;
    cell.ranges = ranges;
    cell.block_bytes = block_bytes(ranges);
    largest_block_ = std::max(largest_block_, cell.block_bytes);
    cells_.push_back(cell);
  }
  const std::vector<streaming::CellFootprint> slots = footprints(volume);
  for (std::size_t k = 0; k < cells_.size(); ++k) cells_[k].slot_bytes = slots[k].bytes;
  // The top level precedes the first cell's nodes (records without faces may list empty ranges at 0).
  for (const CellPart& cell : cells_)
    if (cell.block_bytes > 0) {
      top_nodes_ = cell.ranges.trace_nodes.first;
      break;
    }
  find_parent_words(volume, tracing);
  std::vector<std::byte> global;
  build_global_region(tracing, global);
  const std::uint64_t total = pool_start_ + cell_bytes;
  const std::uint64_t limit = std::min<std::uint64_t>(device.info.max_storage_buffer_range, std::uint64_t(1) << 31);
  if (total > limit)
    fail(StatusCode::unsupported, "streamed tracing arena: " + std::to_string(total) + " bytes exceed " +
                                      std::to_string(limit) + " (maxStorageBufferRange of " + device.info.name +
                                      ", or 2 GiB); lower the budget");
  staging_bytes_ = std::max(staging_bytes, largest_block_);
  constexpr VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  arena_ = device.allocator->create_buffer(total, usage, MemoryUse::device, "streamed tracing arena");
  trees_ = device.allocator->create_buffer(volume.trace_trees.size() * sizeof(gpu::TraceTree), usage, MemoryUse::device,
                                           "streamed trace trees");
  scratch_ = device.allocator->create_buffer(std::max<std::uint64_t>(largest_block_, 16), usage, MemoryUse::device,
                                             "streamed tracing compaction scratch");
  const std::array<VkBuffer, gpu::STREAM_BINDING_COUNT> relocate_buffers{arena_.get(), scratch_.get()};
  relocate_set_ = make_pass_descriptor_set(device.vk(), device.compute_pipelines().set_layout(detail::Layout::stream),
                                           relocate_buffers);
  for (std::uint32_t r = 0; r < rings; ++r)
    staging_.push_back(device.allocator->create_buffer(staging_bytes_, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                       MemoryUse::upload, "streaming staging"));
  // The global region and the trees, once: no cell resident, every cell word the null leaf.
  std::vector<gpu::TraceTree> trees = volume.trace_trees;
  const std::uint64_t tree_bytes = trees.size() * sizeof(gpu::TraceTree);
  Buffer upload = device.allocator->create_buffer(global.size() + tree_bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                  MemoryUse::upload, "upload staging");
  for (std::size_t t = 1; t < trees.size(); ++t)
    if (trees[t].root != gpu::TRACE_NO_ROOT)
      trees[t].root = moved_word(trees[t].root, dyn_node_shift_, dyn_face_shift_);
  auto* top = reinterpret_cast<gpu::TraceNode*>(global.data());
  for (const CellPart& cell : cells_) {
    if (cell.block_bytes == 0) continue;
    if (cell.in_tree_root)
      trees[0].root = null_leaf_;
    else
      top[cell.parent_node].child[cell.parent_child] = null_leaf_;
  }
  std::memcpy(upload.mapped(), global.data(), global.size());
  std::memcpy(static_cast<std::byte*>(upload.mapped()) + global.size(), trees.data(), tree_bytes);
  Submission submission(device);
  vkCmdFillBuffer(submission.cmd(), arena_.get(), 0, VK_WHOLE_SIZE, 0);
  barrier(submission.cmd(), kTransferWrite, kTransferWrite);
  const VkBufferCopy regions[2] = {{0, 0, global.size()}, {global.size(), 0, tree_bytes}};
  vkCmdCopyBuffer(submission.cmd(), upload.get(), arena_.get(), 1, &regions[0]);
  vkCmdCopyBuffer(submission.cmd(), upload.get(), trees_.get(), 1, &regions[1]);
  barrier(submission.cmd(), kTransferWrite, kAnyDeviceAccess);
  submission.submit_and_wait();
}

// Arena bytes [0, pool_start_): the top level (cell words set to the null leaf), the dynamic objects'
// nodes, faces and vertices renumbered to follow it, the null face and its vertex.
void StreamedTracing::build_global_region(const formats::TracingView& tracing, std::vector<std::byte>& bytes) {
  // The dynamic objects' parts follow every cell's.
  std::uint32_t dyn_nodes_from = top_nodes_, dyn_faces_from = 0, dyn_vertices_from = 0;
  for (const CellPart& cell : cells_) {
    const formats::CellTracing& r = cell.ranges;
    dyn_nodes_from = std::max(dyn_nodes_from, r.trace_nodes.first + r.trace_nodes.count);
    dyn_faces_from = std::max(dyn_faces_from, r.trace_faces.first + r.trace_faces.count);
    dyn_vertices_from = std::max(dyn_vertices_from, r.trace_vertices.first + r.trace_vertices.count);
  }
  dynamic_nodes_ = std::uint32_t(tracing.nodes.size()) - dyn_nodes_from;
  const std::uint32_t dyn_faces = std::uint32_t(tracing.faces.size()) - dyn_faces_from;
  const std::uint32_t dyn_vertices = std::uint32_t(tracing.vertices.size()) - dyn_vertices_from;
  const Layout layout(top_nodes_ + dynamic_nodes_, dyn_faces + 1, dyn_vertices + 1);
  pool_start_ = layout.bytes;
  bytes.assign(layout.bytes, std::byte{0});
  const std::uint32_t face_base = std::uint32_t(layout.faces_at / kFaceBytes);
  const std::uint32_t vertex_base = std::uint32_t(layout.vertices_at / kVertexBytes);
  null_leaf_ = leaf_word(face_base + dyn_faces, 1);
  auto* nodes = reinterpret_cast<gpu::TraceNode*>(bytes.data());
  std::copy_n(tracing.nodes.begin(), top_nodes_, nodes);
  dyn_node_shift_ = std::int64_t(top_nodes_) - dyn_nodes_from;
  dyn_face_shift_ = std::int64_t(face_base) - dyn_faces_from;
  for (std::uint32_t i = 0; i < dynamic_nodes_; ++i) {
    gpu::TraceNode n = tracing.nodes[dyn_nodes_from + i];
    for (std::uint32_t& w : n.child) w = moved_word(w, dyn_node_shift_, dyn_face_shift_);
    nodes[top_nodes_ + i] = n;
  }
  auto* faces = reinterpret_cast<gpu::TraceFace*>(bytes.data() + layout.faces_at);
  for (std::uint32_t i = 0; i < dyn_faces; ++i) {
    gpu::TraceFace f = tracing.faces[dyn_faces_from + i];
    for (std::uint32_t& v : f.vertex) v = v - dyn_vertices_from + vertex_base;
    faces[i] = f;
  }
  faces[dyn_faces] = {{vertex_base + dyn_vertices, vertex_base + dyn_vertices, vertex_base + dyn_vertices}, 0u};
  std::memcpy(bytes.data() + layout.vertices_at, tracing.vertices.data() + dyn_vertices_from,
              dyn_vertices * kVertexBytes);
}

std::uint32_t StreamedTracing::cell_root_word(const CellPart& cell) const {
  if (cell.offset < 0) return null_leaf_;
  const std::uint64_t at = pool_start_ + std::uint64_t(cell.offset);
  const formats::CellTracing& r = cell.ranges;
  if (r.trace_nodes.count > 0) return std::uint32_t(at / kNodeBytes);
  const Layout layout(0, r.trace_faces.count, r.trace_vertices.count);
  return leaf_word(std::uint32_t((at + layout.faces_at) / kFaceBytes), r.trace_faces.count);
}

void StreamedTracing::find_parent_words(const formats::ProbeVolume& volume, const formats::TracingView& tracing) {
  std::unordered_map<std::uint32_t, std::size_t> by_file_word; // the cell's root word in the file -> cell
  for (std::size_t k = 0; k < cells_.size(); ++k) {
    const formats::CellTracing& r = cells_[k].ranges;
    if (r.trace_faces.count == 0) continue;
    by_file_word[r.trace_nodes.count > 0 ? r.trace_nodes.first : leaf_word(r.trace_faces.first, r.trace_faces.count)] =
        k;
  }
  const auto claim = [&](std::uint32_t word, auto&& set) {
    if (!formats::is_leaf_word(word) && word < top_nodes_) return; // another top-level node
    const auto it = by_file_word.find(word);
    if (it == by_file_word.end())
      fail(StatusCode::invalid_volume, "cell_tracing: top-level word " + std::to_string(word) +
                                           " leads to no cell's root (" + std::to_string(top_nodes_) +
                                           " top-level nodes)");
    set(cells_[it->second]);
  };
  if (top_nodes_ == 0 && volume.trace_trees[0].root != gpu::TRACE_NO_ROOT)
    claim(volume.trace_trees[0].root, [](CellPart& cell) { cell.in_tree_root = true; });
  for (std::uint32_t n = 0; n < top_nodes_; ++n)
    for (std::uint32_t c = 0; c < 2; ++c)
      claim(tracing.nodes[n].child[c], [&](CellPart& cell) { cell.parent_node = n, cell.parent_child = c; });
}

void StreamedTracing::write_block(const CellPart& cell, const formats::CellTracingData& data, std::uint64_t offset,
                                  std::byte* out) const {
  const formats::CellTracing& r = cell.ranges;
  const Layout layout(r.trace_nodes.count, r.trace_faces.count, r.trace_vertices.count);
  const std::uint64_t at = pool_start_ + offset;
  const std::int64_t node_shift = std::int64_t(at / kNodeBytes) - r.trace_nodes.first;
  const std::int64_t face_shift = std::int64_t((at + layout.faces_at) / kFaceBytes) - r.trace_faces.first;
  const std::int64_t vertex_shift = std::int64_t((at + layout.vertices_at) / kVertexBytes) - r.trace_vertices.first;
  std::memset(out, 0, layout.bytes);
  auto* nodes = reinterpret_cast<gpu::TraceNode*>(out);
  for (std::uint32_t i = 0; i < r.trace_nodes.count; ++i) {
    gpu::TraceNode n = data.nodes[i];
    for (std::uint32_t& w : n.child) w = moved_word(w, node_shift, face_shift);
    nodes[i] = n;
  }
  auto* faces = reinterpret_cast<gpu::TraceFace*>(out + layout.faces_at);
  for (std::uint32_t i = 0; i < r.trace_faces.count; ++i) {
    gpu::TraceFace f = data.faces[i];
    for (std::uint32_t& v : f.vertex) v = std::uint32_t(std::int64_t(v) + vertex_shift);
    faces[i] = f;
  }
  std::memcpy(out + layout.vertices_at, data.vertices.data(), r.trace_vertices.count * kVertexBytes);
}

std::vector<streaming::CellFootprint> StreamedTracing::footprints(const formats::ProbeVolume& volume) {
  std::vector<std::uint64_t> blocks;
  for (std::size_t k = 0; k < volume.cells.size() && k < volume.cell_tracing.size(); ++k)
    blocks.push_back(block_bytes(volume.cell_tracing[k]));
  const std::vector<std::uint64_t> slots = slot_bytes(blocks);
  std::vector<streaming::CellFootprint> out;
  for (std::size_t k = 0; k < slots.size(); ++k)
    out.push_back({volume.cells[k].cell_index, volume.cells[k].bounds_min, volume.cells[k].bounds_max, slots[k]});
  return out;
}

void StreamedTracing::set_word(VkCommandBuffer cmd, const CellPart& cell, std::uint32_t word) {
  if (cell.in_tree_root) {
    vkCmdUpdateBuffer(cmd, trees_.get(), offsetof(gpu::TraceTree, root), sizeof(word), &word);
    return;
  }
  const VkDeviceSize at =
      VkDeviceSize(cell.parent_node) * kNodeBytes + offsetof(gpu::TraceNode, child) + cell.parent_child * sizeof(word);
  vkCmdUpdateBuffer(cmd, arena_.get(), at, sizeof(word), &word);
}

StreamedTracing::Missed StreamedTracing::record(VkCommandBuffer cmd, std::uint32_t ring,
                                                const streaming::ResidencyChanges& changes) {
  Missed missed;
  for (std::size_t k : changes.drops) {
    CellPart& cell = cells_[k];
    if (cell.offset < 0) continue;
    blocks_.release(std::uint64_t(cell.offset), cell.slot_bytes);
    cell.offset = -1;
    set_word(cmd, cell, null_leaf_);
  }
  if (fragmented_for(changes.loads)) missed.compacted = compact(cmd); // before any of this frame's blocks is placed
  auto* staging = static_cast<std::byte*>(staging_[ring].mapped());
  std::uint64_t used = 0;
  std::vector<VkBufferCopy> copies;
  for (std::size_t k : changes.loads) {
    CellPart& cell = cells_[k];
    if (cell.block_bytes == 0) continue;            // a cell without faces: nothing to trace
    if (used + cell.block_bytes > staging_bytes_) { // this frame's staging is full
      missed.unplaced.push_back(k);
      continue;
    }
    // The block is placed before the cell is read: a load that finds no free run in a fragmented arena waits
    // without reading and checking the cell again every frame.
    const std::int64_t offset = blocks_.allocate(cell.slot_bytes);
    if (offset < 0) {
      missed.unplaced.push_back(k);
      continue;
    }
    std::optional<formats::CellTracingData> data;
    try {
      data = reader_ ? reader_->take_or_request(k) : source_->read(k);
    } catch (const Error& e) {
      blocks_.release(std::uint64_t(offset), cell.slot_bytes);
      if (e.kind() != ErrorKind::input) throw;
      missed.refused.emplace_back(k, e.what());
      continue;
    }
    if (!data) {
      blocks_.release(std::uint64_t(offset), cell.slot_bytes);
      missed.reading.push_back(k);
      continue;
    }
    cell.offset = offset;
    write_block(cell, *data, std::uint64_t(offset), staging + used);
    copies.push_back({used, pool_start_ + std::uint64_t(offset), cell.block_bytes});
    used += cell.block_bytes;
  }
  if (reader_) reader_->keep_only(missed.reading); // the others were taken or are no longer wanted
  if (!copies.empty())
    vkCmdCopyBuffer(cmd, staging_[ring].get(), arena_.get(), std::uint32_t(copies.size()), copies.data());
  for (std::size_t k : changes.loads)
    if (cells_[k].offset >= 0) set_word(cmd, cells_[k], cell_root_word(cells_[k]));
  return missed;
}

bool StreamedTracing::fragmented_for(const std::vector<std::size_t>& loads) const {
  BlockAllocator trial = blocks_;
  for (std::size_t k : loads) {
    const std::uint64_t slot = cells_[k].slot_bytes;
    if (slot > 0 && trial.allocate(slot) < 0) return trial.free_bytes() >= slot;
  }
  return false;
}

int StreamedTracing::compact(VkCommandBuffer cmd) {
  std::vector<CellPart*> resident;
  for (CellPart& cell : cells_)
    if (cell.offset >= 0) resident.push_back(&cell);
  std::sort(resident.begin(), resident.end(),
            [](const CellPart* a, const CellPart* b) { return a->offset < b->offset; });
  barrier(cmd, kAnyDeviceAccess, kAnyDeviceAccess); // this frame's word updates, earlier frames' reads
  std::uint64_t cursor = 0;
  int moved = 0;
  for (CellPart* cell : resident) {
    if (std::uint64_t(cell->offset) != cursor) relocate(cmd, *cell, cursor), ++moved;
    cursor += cell->slot_bytes;
  }
  blocks_.compacted(cursor);
  return moved;
}

// The block's bytes go to the scratch buffer and back at `to` (so that a move onto its own old place reads
// nothing it wrote), then stream_relocate rewrites its nodes and faces with their indices shifted.
void StreamedTracing::relocate(VkCommandBuffer cmd, CellPart& cell, std::uint64_t to) {
  const formats::CellTracing& r = cell.ranges;
  const std::uint64_t from_byte = pool_start_ + std::uint64_t(cell.offset), to_byte = pool_start_ + to;
  const VkBufferCopy out{from_byte, 0, cell.block_bytes}, back{0, to_byte, cell.block_bytes};
  vkCmdCopyBuffer(cmd, arena_.get(), scratch_.get(), 1, &out);
  barrier(cmd, kTransferWrite, kTransferRead);
  vkCmdCopyBuffer(cmd, scratch_.get(), arena_.get(), 1, &back);
  barrier(cmd, kTransferWrite, kComputeReadWrite);
  Pipelines& p = device_.compute_pipelines();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.kernel(Kernel::stream_relocate));
  bind_pass_set_and_push(cmd, p.layout(detail::Layout::stream), relocate_set_.set,
                         gpu::StreamRelocatePush{std::uint32_t(from_byte), std::uint32_t(to_byte), r.trace_nodes.count,
                                                 r.trace_faces.count});
  const std::uint32_t items = r.trace_nodes.count + r.trace_faces.count;
  dispatch_groups(cmd, device_, (items + gpu::RUNTIME_WORKGROUP_SIZE - 1) / gpu::RUNTIME_WORKGROUP_SIZE);
  barrier(cmd, kAnyDeviceAccess, kAnyDeviceAccess); // the next block's copies reuse the scratch and may overlap
  cell.offset = std::int64_t(to);
  set_word(cmd, cell, cell_root_word(cell));
}

std::vector<std::string> StreamedTracing::verify(const formats::ProbeVolume& file) const {
  const VkDeviceSize arena_bytes = arena_.size(), tree_bytes = trees_.size();
  Buffer back = device_.allocator->create_buffer(arena_bytes + tree_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                 MemoryUse::readback, "read-back staging");
  {
    Submission submission(device_);
    barrier(submission.cmd(), kAnyDeviceAccess, kTransferRead);
    const VkBufferCopy regions[2] = {{0, 0, arena_bytes}, {0, arena_bytes, tree_bytes}};
    vkCmdCopyBuffer(submission.cmd(), arena_.get(), back.get(), 1, &regions[0]);
    vkCmdCopyBuffer(submission.cmd(), trees_.get(), back.get(), 1, &regions[1]);
    barrier(submission.cmd(), kTransferWrite, kHostRead);
    submission.submit_and_wait();
  }
  const auto* bytes = static_cast<const std::byte*>(back.mapped());
  std::vector<std::byte> expected(largest_block_);
  std::vector<std::string> problems;
  for (std::size_t k = 0; k < cells_.size() && problems.size() < 8; ++k) {
    const CellPart& cell = cells_[k];
    if (cell.block_bytes == 0) continue;
    std::uint32_t word = 0;
    if (cell.in_tree_root)
      std::memcpy(&word, bytes + arena_bytes + offsetof(gpu::TraceTree, root), sizeof(word));
    else
      std::memcpy(&word,
                  bytes + cell.parent_node * kNodeBytes + offsetof(gpu::TraceNode, child) + cell.parent_child * 4,
                  sizeof(word));
    if (word != cell_root_word(cell)) {
      problems.push_back("cell record " + std::to_string(k) + ": the word leading to it is " + std::to_string(word) +
                         ", not " + std::to_string(cell_root_word(cell)) + (cell.offset < 0 ? " (the null leaf)" : ""));
      continue;
    }
    if (cell.offset < 0) continue;
    write_block(cell, formats::cell_tracing_data(file, k), std::uint64_t(cell.offset), expected.data());
    if (std::memcmp(expected.data(), bytes + pool_start_ + std::uint64_t(cell.offset), cell.block_bytes) != 0)
      problems.push_back("cell record " + std::to_string(k) + ": its block in the arena differs from the file's bytes");
  }
  return problems;
}

} // namespace probebake::runtime::detail
