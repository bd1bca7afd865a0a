// The memory update's frames (memory_update_pass.h): the host's FrameInputs checked, then recorded into the
// frame's command buffer with the cell changes that fit, the light transitions and the end of the frame, and
// each frame's statistics. The pass's setup is in memory_update_pass.cpp.
#include "memory_update/memory_update_pass.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/common.hpp>

#include "core/error.h"
#include "probebake/formats/octree.h"

namespace probebake::runtime::detail {
namespace {

constexpr Access kAnyDeviceAndIndirect{kAnyDeviceAccess.stages | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                                       kAnyDeviceAccess.access | VK_ACCESS_INDIRECT_COMMAND_READ_BIT};

bool finite_box(const Box& b) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(b.min[a]) || !std::isfinite(b.max[a]) || b.min[a] > b.max[a]) return false;
  return true;
}

bool unit_interval(float x) { return x >= 0.0f && x <= 1.0f; }

// The frame's boxes as the shaders take them: beyond MEMORY_MAX_BOXES, the rest are merged into the last.
gpu::MemoryFrame to_frame(const FrameInputs& in, std::span<const Box> moved_boxes, int batches,
                          std::uint32_t null_leaf) {
  gpu::MemoryFrame f{};
  f.null_leaf = null_leaf;
  f.max_memory_entries = in.limits.max_memory_entries;
  f.max_light_entries = in.limits.max_light_entries;
  f.dead_backface_fraction = in.dead_backface_fraction;
  f.batches_per_probe = batches;
  int b = 0; // boxes past MEMORY_MAX_BOXES are merged into the last one
  const auto add = [&](const Box& box) {
    const int slot = std::min<int>(b, gpu::MEMORY_MAX_BOXES - 1);
    gpu::MemoryBox& out = f.boxes[slot];
    if (slot < b) {
      out.lower = glm::min(out.lower, box.min);
      out.upper = glm::max(out.upper, box.max);
    } else {
      out.lower = box.min;
      out.upper = box.max;
    }
    f.box_count = slot + 1;
    ++b;
  };
  for (const Box& box : in.changed_boxes) add(box);
  for (const Box& box : moved_boxes) add(box);
  return f;
}

} // namespace

Status check_frame_inputs(const FrameInputs& in) {
  auto bad = [](const std::string& what) { return Status{StatusCode::invalid_argument, "run_frame: " + what}; };
  for (std::size_t b = 0; b < in.changed_boxes.size(); ++b)
    if (!finite_box(in.changed_boxes[b]))
      return bad("changed box " + std::to_string(b) + " is not finite with min <= max");
  if (in.max_depth && (*in.max_depth < 0 || *in.max_depth > gpu::OCTREE_MAX_DEPTH))
    return bad("max_depth " + std::to_string(*in.max_depth) + " outside [0, " + std::to_string(gpu::OCTREE_MAX_DEPTH) +
               "]");
  if (in.split_low && !unit_interval(*in.split_low)) return bad("split_low outside [0, 1]");
  if (in.split_high && !unit_interval(*in.split_high)) return bad("split_high outside [0, 1]");
  if (in.split_low && in.split_high && *in.split_low > *in.split_high) return bad("split_low above split_high");
  if (!unit_interval(in.dead_backface_fraction)) return bad("dead_backface_fraction outside [0, 1]");
  if (in.limits.max_memory_entries < 0 || in.limits.max_light_entries < 0 || in.limits.max_gathered_probes < 0 ||
      in.limits.max_traced_probes < 0)
    return bad("negative per-frame limit");
  if (!(in.limits.frame_ms >= 0.0f && in.limits.frame_ms <= 1e6f))
    return bad("frame_ms " + std::to_string(in.limits.frame_ms) + " is not in [0, 1e6]");
  if (in.limits.shadow_rays_per_record < 0 || in.limits.shadow_rays_per_record == 1 ||
      in.limits.shadow_rays_per_record > 9)
    return bad("shadow_rays_per_record " + std::to_string(in.limits.shadow_rays_per_record) + " is not 0 or in [2, 9]");
  if (in.limits.relight_frames < 0 || in.limits.relight_frames > 64)
    return bad("relight_frames " + std::to_string(in.limits.relight_frames) + " is not in [0, 64]");
  return {};
}

void MemoryUpdatePass::dispatch(VkCommandBuffer cmd, VkPipeline pipeline, std::uint32_t threads,
                                std::uint32_t group_size) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  dispatch_groups(cmd, device_, std::max<std::uint32_t>(1, (threads + group_size - 1) / group_size));
  // Every step reads what the one before wrote, and may overwrite what it read; the state buffer (written
  // through its descriptor, as a whole for the validator) is also where the dispatch sizes are read.
  barrier(cmd, kComputeReadWrite, kComputeAndIndirect);
}

void MemoryUpdatePass::dispatch_indirect(VkCommandBuffer cmd, VkPipeline pipeline, VkDeviceSize offset) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  vkCmdDispatchIndirect(cmd, state_.get(), offset);
  barrier(cmd, kComputeReadWrite, kComputeAndIndirect);
}

void MemoryUpdatePass::bind(VkCommandBuffer cmd, const gpu::MemoryPush& push) const {
  bind_sets_and_push(cmd, device_.compute_pipelines().layout(Layout::memory), volume_.volume_set(), descriptors_.set,
                     push);
}

void MemoryUpdatePass::begin(VkCommandBuffer cmd, VkPipeline pipeline) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  vkCmdDispatch(cmd, 1, 1, 1);
  barrier(cmd, kComputeReadWrite, kComputeAndIndirect);
}

void MemoryUpdatePass::record_memory_update(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t slot,
                                            const FrameInputs& inputs, std::span<const Box> moved_boxes) {
  Pipelines& p = device_.compute_pipelines();
  gpu::MemoryFrame frame = to_frame(inputs, moved_boxes, batches_per_probe_, null_leaf_);
  const bool thresholds = inputs.max_depth || inputs.split_low || inputs.split_high;
  if (inputs.max_depth) info_.max_depth = *inputs.max_depth;
  if (inputs.split_low) info_.split_low = *inputs.split_low;
  if (inputs.split_high) info_.split_high = *inputs.split_high;
  std::vector<std::int32_t> seat_data;
  const auto seats = std::uint32_t(take_cell_changes(frame, seat_data));
  const auto cells = std::uint32_t(frame.cell_changes);
  timer.begin(cmd, slot);
  vkCmdUpdateBuffer(cmd, frame_.get(), 0, sizeof(frame), &frame);
  constexpr std::size_t kChunk = 65536 / sizeof(std::int32_t); // vkCmdUpdateBuffer's limit
  for (std::size_t i = 0; i < seat_data.size(); i += kChunk)
    vkCmdUpdateBuffer(cmd, frame_.get(), sizeof(frame) + i * sizeof(std::int32_t),
                      std::min(kChunk, seat_data.size() - i) * sizeof(std::int32_t), seat_data.data() + i);
  if (thresholds) vkCmdUpdateBuffer(cmd, volume_.buffer(Section::volume_info).get(), 0, sizeof(info_), &info_);
  vkCmdFillBuffer(cmd, counters_.buffer(), 0, VK_WHOLE_SIZE, 0);
  barrier(cmd, kTransferWrite, kComputeReadWrite);
  bind(cmd, gpu::MemoryPush{0, 0, 0, 0});
  const std::uint32_t group = gpu::MEMORY_WORKGROUP_SIZE;
  constexpr VkDeviceSize kPerEntryGroups = offsetof(gpu::MemoryState, entry_groups);
  constexpr VkDeviceSize kPerEntryThreads = offsetof(gpu::MemoryState, entry_thread_groups);
  begin(cmd, p.kernel(Kernel::memory_begin));
  dispatch_indirect(cmd, p.kernel(Kernel::memory_decide), kPerEntryGroups);
  dispatch_indirect(cmd, p.kernel(Kernel::memory_release), kPerEntryThreads);
  dispatch(cmd, p.kernel(Kernel::memory_grant), 1, 1);
  dispatch_indirect(cmd, p.kernel(Kernel::memory_allocate), kPerEntryThreads);
  dispatch_indirect(cmd, p.kernel(Kernel::memory_collapse), kPerEntryThreads);
  if (cells > 0) { // drops in parallel (pushes only), the arrivals' pops by one thread, their subtrees in parallel
    dispatch(cmd, p.kernel(Kernel::memory_cells), cells, group);
    bind(cmd, gpu::MemoryPush{1, 0, 0, 0});
    dispatch(cmd, p.kernel(Kernel::memory_cells), 1, group);
    if (seats > 0) {
      bind(cmd, gpu::MemoryPush{2, 0, 0, 0});
      dispatch(cmd, p.kernel(Kernel::memory_cells), seats * group, group); // a workgroup per seat
      bind(cmd, gpu::MemoryPush{3, 0, 0, 0});
      dispatch(cmd, p.kernel(Kernel::memory_cells), seats * group, group); // their stencils, every seat written
    }
    bind(cmd, gpu::MemoryPush{0, 0, 0, 0});
  }
  if (std::exchange(remeasure_, false))
    dispatch(cmd, p.kernel(Kernel::memory_remeasure), std::uint32_t(info_.octree_elements), group);
  dispatch(cmd, p.kernel(Kernel::memory_svo), std::uint32_t(info_.svo_leaves), group);
  timer.end(cmd, slot);
  // The probe index build and the light update read the tree, probes and SVO (compute, transfer).
  barrier(cmd, kComputeReadWrite, kAnyDeviceAccess);
}

void MemoryUpdatePass::record_light_transitions(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t slot) {
  Pipelines& p = device_.compute_pipelines();
  // Last frame's indirect dispatches read the light list that memory_begin empties (write after read).
  barrier(cmd, kAnyDeviceAndIndirect, kComputeReadWrite);
  timer.begin(cmd, slot);
  bind(cmd, gpu::MemoryPush{1, 0, 0, 0});
  begin(cmd, p.kernel(Kernel::memory_begin));
  dispatch_indirect(cmd, p.kernel(Kernel::memory_light), offsetof(gpu::MemoryState, light_groups));
  bind(cmd, gpu::MemoryPush{2, 0, 0, 0});
  begin(cmd, p.kernel(Kernel::memory_begin));
  timer.end(cmd, slot);
  // The light update reads the probes, flags and list in its shaders and the list's sizes as dispatch sizes.
  barrier(cmd, kComputeReadWrite, kAnyDeviceAndIndirect);
}

void MemoryUpdatePass::record_end_of_frame(VkCommandBuffer cmd, std::uint32_t ring) {
  Pipelines& p = device_.compute_pipelines();
  barrier(cmd, kAnyDeviceAccess, kComputeReadWrite);
  bind(cmd, gpu::MemoryPush{});
  dispatch(cmd, p.kernel(Kernel::memory_sync), 3 * segment_capacity_, gpu::MEMORY_WORKGROUP_SIZE);
  counters_.record_end_of_pass_copy(cmd, ring);
}

void MemoryUpdatePass::change_cells(std::span<const std::uint32_t> changes) {
  cell_changes_.insert(cell_changes_.end(), changes.begin(), changes.end());
}

std::size_t MemoryUpdatePass::take_cell_changes(gpu::MemoryFrame& frame, std::vector<std::int32_t>& seat_data) {
  std::vector<gpu::CellSeat> headers;
  std::vector<std::int32_t> body;
  std::size_t taken = 0;
  for (; taken < cell_changes_.size() && taken < std::size_t(gpu::MEMORY_MAX_CELL_CHANGES); ++taken) {
    std::uint32_t entry = cell_changes_[taken];
    if ((entry & gpu::MEMORY_CELL_ARRIVED) != 0) {
      const std::size_t k = entry & ~gpu::MEMORY_CELL_ARRIVED;
      if (k >= seats_.size()) fail(StatusCode::internal, "memory update: an arrival names no cell record");
      const SeatPayload& payload = seats_[k];
      const std::size_t payload_ints = payload.ints();
      const bool fits_alone =
          gpu::SEAT_HEADER_INTS + payload_ints <= seat_ints_; // else it grows by measures (CellSeat::clusters -1)
      if (gpu::SEAT_HEADER_INTS * (headers.size() + 1) + body.size() + (fits_alone ? payload_ints : 0) > seat_ints_ ||
          headers.size() >= segment_capacity_) // the seats' work lives in memory_work: one entry each
        break;                                 // the rest wait
      gpu::CellSeat seat = payload.seat;
      seat.first_word = seat.first_probe = seat.first_svo = int(body.size());
      if (fits_alone) {
        body.insert(body.end(), payload.words.begin(), payload.words.end());
        seat.first_probe = int(body.size());
        body.resize(body.size() + payload.probes.size() * gpu::SEAT_PROBE_INTS);
        std::memcpy(body.data() + seat.first_probe, payload.probes.data(), payload.probes.size() * sizeof(gpu::Probe));
        seat.first_svo = int(body.size());
        body.insert(body.end(), payload.svo.begin(), payload.svo.end());
      } else {
        seat.clusters = -1;
        seat.probes = 0;
        seat.svo_leaves = 0;
      }
      entry = gpu::MEMORY_CELL_ARRIVED | std::uint32_t(headers.size());
      headers.push_back(seat);
    }
    frame.cells[taken] = entry;
  }
  frame.cell_changes = int(taken);
  frame.cell_depth = cell_depth_;
  cell_changes_.erase(cell_changes_.begin(), cell_changes_.begin() + std::ptrdiff_t(taken));
  const int offset = int(gpu::SEAT_HEADER_INTS * headers.size()); // the bodies follow the headers
  for (gpu::CellSeat& seat : headers) seat.first_word += offset, seat.first_probe += offset, seat.first_svo += offset;
  seat_data.resize(gpu::SEAT_HEADER_INTS * headers.size());
  std::memcpy(seat_data.data(), headers.data(), headers.size() * sizeof(gpu::CellSeat));
  seat_data.insert(seat_data.end(), body.begin(), body.end());
  return headers.size();
}

MemoryUpdateStats MemoryUpdatePass::stats(std::uint32_t ring) const {
  const gpu::MemoryCounters c = counters_.read(ring);
  MemoryUpdateStats s;
  s.active = true;
  std::copy(std::begin(c.processed), std::end(c.processed), s.processed.begin());
  s.deferred = c.deferred;
  s.probes_placed = c.probes_placed;
  s.probes_freed = c.probes_freed;
  s.splits = c.splits;
  s.collapses = c.collapses;
  s.failed_allocations = c.failed_allocations;
  s.lost_entries = c.lost_entries;
  s.stale_entries = c.stale_entries;
  s.svo_slots_dropped = c.svo_slots_dropped;
  s.svo_leaves_refilled = c.svo_leaves_refilled;
  s.free_clusters = c.free_clusters;
  s.free_probes = c.free_probes;
  s.free_batches = c.free_batches;
  s.unresolved_measures = c.unresolved_measures;
  s.cells_collapsed = c.cells_collapsed;
  s.cluster_capacity = int(formats::complete_clusters(std::size_t(info_.octree_elements)));
  s.probe_capacity = info_.probe_capacity;
  s.batch_capacity = info_.batch_capacity;
  return s;
}

} // namespace probebake::runtime::detail
