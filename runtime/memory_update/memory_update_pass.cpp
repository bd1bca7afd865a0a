// The memory update's setup (memory_update_pass.h): the volume prepared for it, the pass's buffers and
// free-list stacks uploaded, and with streaming each cell's seat (the file's subtree it gets back). Each
// frame's checks, recording and statistics are in memory_update_frame.cpp.
#include "memory_update/memory_update_pass.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/error.h"
#include "memory_update/memory_update_bindings.h"
#include "probebake/dynamic/tree_update.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/octree.h"
#include "probebake/leaf_rule.h"

namespace probebake::runtime::detail {
namespace {

constexpr VkBufferUsageFlags kUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

// Where each probe of `v` sits: its leaf's depth and integer coordinates at that depth (depth -1: a free
// probe). Walks the tree with an explicit stack, no deeper than OCTREE_MAX_DEPTH.
std::vector<NodeKey> probe_node_keys(const formats::ProbeVolume& v) {
  std::vector<NodeKey> keys(v.probes.size(), NodeKey{0, 0, 0, -1});
  std::vector<NodeKey> stack{NodeKey{0, 0, 0, 0}}; // here .x/.y/.z/.depth of a node, and its index below
  std::vector<int> nodes{0};
  while (!nodes.empty()) {
    const NodeKey at = stack.back();
    const int node = nodes.back();
    stack.pop_back(), nodes.pop_back();
    const int value = v.octree[std::size_t(node)];
    if (value < 0 && std::size_t(~value) < keys.size()) keys[std::size_t(~value)] = at;
    if (value <= 0 || at.depth >= gpu::OCTREE_MAX_DEPTH || std::size_t(value) + 9 > v.octree.size()) continue;
    for (int o = 0; o < 8; ++o) {
      stack.push_back(NodeKey{2 * at.x + (o & 1), 2 * at.y + ((o >> 1) & 1), 2 * at.z + ((o >> 2) & 1), at.depth + 1});
      nodes.push_back(value + 1 + o);
    }
  }
  return keys;
}

int batches_per_probe(const formats::ProbeVolume& v) {
  if (v.surfel_batches.empty()) return 0;
  return (v.info.surfels_per_probe + gpu::SURFELS_PER_BATCH - 1) / gpu::SURFELS_PER_BATCH;
}

// A device buffer holding `bytes` of `data` (at least 16 bytes, zero-padded), uploaded and waited for.
Buffer upload(Device& device, const void* data, std::size_t bytes, const std::string& name,
              VkBufferUsageFlags extra = 0) {
  const std::size_t size = std::max<std::size_t>(bytes, 16);
  if (size > device.info.max_storage_buffer_range)
    fail(StatusCode::unsupported, name + ": " + std::to_string(size) + " bytes exceed maxStorageBufferRange (" +
                                      std::to_string(device.info.max_storage_buffer_range) + ") of " +
                                      device.info.name);
  Buffer buffer = device.allocator->create_buffer(size, kUsage | extra, MemoryUse::device, name);
  Buffer staging =
      device.allocator->create_buffer(size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::upload, name + " staging");
  std::memset(staging.mapped(), 0, size);
  if (data && bytes > 0) std::memcpy(staging.mapped(), data, bytes);
  Submission submission(device);
  const VkBufferCopy region{0, 0, size};
  vkCmdCopyBuffer(submission.cmd(), staging.get(), buffer.get(), 1, &region);
  barrier(submission.cmd(), kTransferWrite, kAnyDeviceAccess);
  submission.submit_and_wait();
  return buffer;
}

template <class T>
Buffer upload(Device& device, const std::vector<T>& values, const std::string& name) {
  return upload(device, values.data(), values.size() * sizeof(T), name);
}

// Free-list stacks as formats::Octree keeps them: filled from the highest index down, so the top (the next
// element allocated) is the lowest free index.
std::vector<int> free_stack(std::size_t count, int first, int stride, const std::function<bool(int)>& is_free) {
  std::vector<int> stack;
  for (std::size_t k = count; k-- > 0;) {
    const int index = first + int(k) * stride;
    if (is_free(index)) stack.push_back(index);
  }
  return stack;
}

std::vector<int> sized(std::vector<int> stack, std::size_t capacity) {
  stack.resize(std::max(stack.size(), capacity), 0);
  return stack;
}

// Centre of every SVO leaf's voxel and the SVO node that holds it (the SVO's shape never changes), for the
// refresh's refill and detach.
std::vector<glm::vec4> svo_leaf_centres(const formats::ProbeVolume& v) {
  std::vector<glm::vec4> centres(v.svo_leaves.size(), glm::vec4(0.0f));
  struct Item {
    int node;
    glm::vec3 min;
    float size;
    int depth;
  };
  std::vector<Item> stack;
  if (v.svo_nodes.size() >= (1u << 24)) fail(StatusCode::unsupported, "memory update: more than 2^24 SVO nodes");
  if (!v.svo_nodes.empty()) stack.push_back({0, v.info.root_min, v.info.root_size, 0});
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    const int value = v.svo_nodes[std::size_t(item.node)];
    if (value < 0 && std::size_t(~value) < centres.size())
      centres[std::size_t(~value)] =
          glm::vec4(item.min + glm::vec3(0.5f * item.size), float(item.node)); // exact below 2^24
    if (value <= 0 || item.depth >= 30) continue;
    for (int o = 0; o < 8; ++o) {
      if (std::size_t(value + o) >= v.svo_nodes.size()) break;
      const float half = 0.5f * item.size;
      stack.push_back({value + o, item.min + glm::vec3(float(o & 1), float((o >> 1) & 1), float((o >> 2) & 1)) * half,
                       half, item.depth + 1});
    }
  }
  return centres;
}

// The bake's stencils of `file`'s SVO leaves with their probes as node keys (SEAT_STENCIL_VEC4S), appended
// to the leaf centres for the seats to restore.
void append_bake_stencils(std::vector<glm::vec4>& bake, const formats::ProbeVolume& file,
                          const std::vector<NodeKey>& keys) {
  for (const gpu::SvoLeaf& stencil : file.svo_leaves) {
    std::array<std::int32_t, 8> key_words{-1, -1, -1, -1, 0, 0, 0, 0}; // x | y << 16 per probe, then z | depth << 16
    for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k) {
      const int probe = stencil.probes[k];
      if (probe < 0 || std::size_t(probe) >= keys.size() || keys[std::size_t(probe)].depth < 0) continue;
      const NodeKey& key = keys[std::size_t(probe)];
      key_words[std::size_t(k)] = key.x | (key.y << 16);
      key_words[std::size_t(4 + k)] = key.z | (key.depth << 16);
    }
    glm::vec4 words[2];
    std::memcpy(words, key_words.data(), sizeof(words));
    bake.insert(bake.end(), {words[0], words[1], stencil.weights});
  }
}

} // namespace

bool memory_update_applies(const formats::ProbeVolume& v) {
  return v.info.placement == gpu::PLACEMENT_OCTREE && !v.octree.empty() && !v.probes.empty() && v.lighting &&
         v.lighting->placement_rays > 0;
}

formats::ProbeVolume prepare_for_memory_update(formats::ProbeVolume v, const MemoryPools& pools, SeatRoom seats) {
  {
    formats::Octree grow(v, formats::Octree::Growth::automatic);
    const auto room = [](int requested, std::uint64_t used, std::uint64_t seat, std::uint64_t least) {
      return requested >= 0 ? requested
                            : int(std::min<std::uint64_t>(seat + std::max(least, used + seat), std::uint64_t(1) << 30));
    };
    const int free_probes =
        room(pools.free_probes, v.probes.size() - std::size_t(grow.free_probes()), seats.probes, 512);
    grow.reserve_clusters(room(pools.free_clusters,
                               formats::complete_clusters(v.octree.size()) - std::size_t(grow.free_clusters()),
                               seats.clusters, 64));
    grow.reserve_probes(free_probes);
    if (!v.surfel_batches.empty())
      grow.reserve_batches(pools.free_batches >= 0 ? pools.free_batches : free_probes * batches_per_probe(v));
  }
  if (v.leaf_entries.empty() || v.leaf_header.segment_capacity < int(v.octree.size())) {
    v.leaf_entries.clear();
    v.leaf_header = gpu::LeafQueueHeader{};
  }
  {
    formats::Octree fixed(v, formats::Octree::Growth::fixed);
    const dynamic::TreeUpdate seed(fixed); // seeds an empty queue with every leaf
  }
  formats::sync_info_counts(v);
  formats::rebuild_probe_index(v);
  return v;
}

MemoryUpdatePass::MemoryUpdatePass(Device& device, const GpuVolume& volume, const formats::ProbeVolume& v,
                                   VkBuffer trace_flags, VkBuffer light_list, std::uint32_t rings,
                                   std::uint32_t seat_ints, const formats::ProbeVolume* cells_file)
    : device_(device),
      volume_(volume),
      info_(v.info),
      batches_per_probe_(batches_per_probe(v)),
      segment_capacity_(std::uint32_t(v.leaf_header.segment_capacity)),
      seat_ints_(std::min(seat_ints, std::uint32_t(gpu::MEMORY_SEAT_INTS))) {
  const std::size_t capacity = segment_capacity_;
  std::vector<int> keys(3 * capacity, 0);
  for (int s = 0; s < 3; ++s)
    for (int e = 0; e < v.leaf_header.count[s]; ++e) {
      const gpu::LeafEntry& entry = v.leaf_entries[std::size_t(s) * capacity + std::size_t(e)];
      if (entry.node < 0 || std::size_t(entry.node) >= capacity) continue; // the validator refuses such entries
      keys[std::size_t(s) * capacity + std::size_t(entry.node)] =
          (gpu::leaf_state_priority(entry.state) << 4) | entry.state;
    }
  const std::vector<int> clusters = free_stack(formats::complete_clusters(v.octree.size()), 1, gpu::OCTREE_CLUSTER_SIZE,
                                               [&](int meta) { return v.octree[std::size_t(meta)] == 0; });
  const std::vector<int> probes =
      free_stack(v.probes.size(), 0, 1, [&](int p) { return v.probes[std::size_t(p)].link == 0; });
  const std::vector<int> batches =
      free_stack(v.surfel_batches.size(), 0, 1, [&](int b) { return v.surfel_batches[std::size_t(b)].link == 0; });
  // Each stack holds its whole pool (every element may be free at once), one after the other.
  std::vector<int> stacks = sized(clusters, formats::complete_clusters(v.octree.size()));
  gpu::MemoryState state{};
  state.cluster_top = int(clusters.size());
  state.probe_top = int(probes.size());
  state.batch_top = int(batches.size());
  state.probe_stack_base = int(stacks.size());
  const std::vector<int> probe_stack = sized(probes, v.probes.size());
  stacks.insert(stacks.end(), probe_stack.begin(), probe_stack.end());
  state.batch_stack_base = int(stacks.size());
  const std::vector<int> batch_stack = sized(batches, v.surfel_batches.size());
  stacks.insert(stacks.end(), batch_stack.begin(), batch_stack.end());

  std::vector<int> state_and_keys(sizeof(state) / sizeof(int) + keys.size());
  std::memcpy(state_and_keys.data(), &state, sizeof(state));
  std::copy(keys.begin(), keys.end(), state_and_keys.begin() + sizeof(state) / sizeof(int));
  state_ = upload(device, state_and_keys.data(), state_and_keys.size() * sizeof(int), "memory: state and queue keys",
                  VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT);
  free_stacks_ = upload(device, stacks, "memory: free-list stacks");
  work_ = upload(device, nullptr, capacity * sizeof(gpu::MemoryWork), "memory: work");
  merge_sh_ = upload(device, nullptr, capacity * gpu::PROBE_SH_FLOATS * sizeof(float), "memory: merge irradiance");
  marks_ = upload(device, nullptr, v.octree.size() * sizeof(int), "memory: node marks");
  frame_ =
      upload(device, nullptr, sizeof(gpu::MemoryFrame) + seat_ints_ * sizeof(std::int32_t), "memory: frame inputs");
  probe_generations_ = upload(device, nullptr, v.probes.size() * sizeof(std::uint32_t), "memory: probe generations");
  svo_generations_ =
      upload(device, nullptr, v.svo_leaves.size() * 4 * sizeof(std::uint32_t), "memory: SVO generations");
  std::vector<glm::vec4> svo_bake = svo_leaf_centres(v);
  if (cells_file) {
    const std::vector<NodeKey> probe_keys = probe_node_keys(*cells_file);
    set_cell_seats(*cells_file);
    add_seat_stencils(*cells_file, probe_keys);
    append_bake_stencils(svo_bake, *cells_file, probe_keys);
  }
  svo_bake_ = upload(device, svo_bake, "memory: SVO leaf centres and bake stencils");
  counters_ = PassCounters<gpu::MemoryCounters>(device, "memory counters", rings);

  std::array<VkBuffer, gpu::MEMORY_BINDING_COUNT> buffers{};
  buffers[gpu::MEMORY_BINDING_STATE] = state_.get();
  buffers[gpu::MEMORY_BINDING_FREE_STACKS] = free_stacks_.get();
  buffers[gpu::MEMORY_BINDING_WORK] = work_.get();
  buffers[gpu::MEMORY_BINDING_MERGE_SH] = merge_sh_.get();
  buffers[gpu::MEMORY_BINDING_MARKS] = marks_.get();
  buffers[gpu::MEMORY_BINDING_FRAME] = frame_.get();
  buffers[gpu::MEMORY_BINDING_COUNTERS] = counters_.buffer();
  buffers[gpu::MEMORY_BINDING_TRACE_FLAGS] = trace_flags;
  buffers[gpu::MEMORY_BINDING_PROBE_GENERATIONS] = probe_generations_.get();
  buffers[gpu::MEMORY_BINDING_SVO_GENERATIONS] = svo_generations_.get();
  buffers[gpu::MEMORY_BINDING_SVO_BAKE] = svo_bake_.get();
  buffers[gpu::MEMORY_BINDING_LIGHT_LIST] = light_list;
  descriptors_ = make_pass_descriptor_set(device.vk(), device.compute_pipelines().set_layout(Layout::memory), buffers);
}

void MemoryUpdatePass::set_cell_seats(const formats::ProbeVolume& file) {
  cell_depth_ = file.cell_depth;
  seats_.assign(file.cells.size(), {});
  for (std::size_t k = 0; k < file.cells.size(); ++k) {
    SeatPayload& out = seats_[k];
    out.seat.cell = std::uint32_t(file.cells[k].cell_index);
    const int root = formats::cell_root_node(file, file.cell_depth, file.cells[k].cell_index);
    if (root < 0) continue; // a leaf above the cell: nothing of its own
    // Clusters in breadth-first order, so that a cluster's parent is seated before it.
    std::vector<int> metas; // local cluster -> the file's meta index
    const auto word_of = [&](int node) {
      const int v = file.octree[std::size_t(node)];
      if (v > 0) {
        metas.push_back(v);
        return std::int32_t(metas.size());
      }
      if (v < 0) {
        out.probes.push_back(file.probes[std::size_t(~v)]);
        return ~std::int32_t(out.probes.size() - 1);
      }
      return std::int32_t(0);
    };
    std::vector<int> parent_slots; // per local cluster
    out.seat.node_word = word_of(root);
    if (!metas.empty()) parent_slots.push_back(-1);
    for (std::size_t c = 0; c < metas.size(); ++c) {
      out.words.push_back(parent_slots[c]);
      for (int o = 0; o < 8; ++o) {
        const std::size_t before = metas.size();
        out.words.push_back(word_of(metas[c] + 1 + o));
        if (metas.size() > before) parent_slots.push_back(int(8 * c) + o);
      }
    }
    out.seat.clusters = int(metas.size());
    out.seat.probes = int(out.probes.size());
  }
}

// Every SVO leaf whose bake stencil names a probe of a cell is named by that cell's seat: memory_cells
// restores the stencil once every arrival of the frame is seated, where all its probes are leaves with
// probes again, whichever cells they lie in (the others keep what memory_svo refills them with).
void MemoryUpdatePass::add_seat_stencils(const formats::ProbeVolume& file, const std::vector<NodeKey>& keys) {
  std::unordered_map<int, std::size_t> record_of_cell;
  for (std::size_t k = 0; k < file.cells.size(); ++k) record_of_cell[file.cells[k].cell_index] = k;
  const int n = 1 << cell_depth_;
  std::vector<std::size_t> records; // of one leaf
  for (std::size_t leaf = 0; leaf < file.svo_leaves.size(); ++leaf) {
    records.clear();
    for (int k = 0; k < gpu::SVO_PROBES_PER_LEAF; ++k) {
      const int probe = file.svo_leaves[leaf].probes[k];
      if (probe < 0 || std::size_t(probe) >= keys.size()) continue;
      const NodeKey& key = keys[std::size_t(probe)];
      if (key.depth < cell_depth_) continue; // above the cells (or free): never dropped
      const int shift = key.depth - cell_depth_;
      const auto record = record_of_cell.find((key.x >> shift) + n * ((key.y >> shift) + n * (key.z >> shift)));
      if (record != record_of_cell.end() && std::find(records.begin(), records.end(), record->second) == records.end())
        records.push_back(record->second);
    }
    for (std::size_t record : records) {
      seats_[record].svo.push_back(std::int32_t(leaf));
      ++seats_[record].seat.svo_leaves;
    }
  }
}

} // namespace probebake::runtime::detail
