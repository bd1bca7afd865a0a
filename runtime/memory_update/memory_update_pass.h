// The memory update (octree thesis §3.2.1: M0-M4) and the light update's state transitions (§3.2.2: L0-L3)
// on the GPU, following dynamic::TreeUpdate (the CPU reference) rule for rule: shaders/memory_*.comp.
// The leaf queue's three segments are key -> state sets (a key per node and segment); node clusters, probes
// and surfel batches come from free-list stacks (pushed with atomics, popped in ranges granted by one thread
// in queue order), never from scans. docs/RUNTIME_INTERNALS.md lists the dispatches and barriers.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "core/allocator.h"
#include "core/commands.h"
#include "core/device.h"
#include "core/gpu_volume.h"
#include "core/handles.h"
#include "core/pass_counters.h"
#include "core/pipelines.h"
#include "probebake/formats/probe_volume.h"
#include "probebake/memory_types.h"
#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

// Whether `volume` can run the memory update: octree placement with probes, the lighting sections.
bool memory_update_applies(const formats::ProbeVolume& volume);

// Room in the pools for subtrees that arrive (streaming: the resident cells'), beyond the tree in use.
struct SeatRoom {
  std::uint64_t probes = 0, clusters = 0;
};

// The volume the GPU starts from: pools grown to `pools`' free counts, and a leaf queue holding every node
// (seeded with every leaf, L2 / L3, when it has none or one too small). Counts and probe index synced. A
// default count is `seats` plus as much again as the tree then uses (at least 512 probes, 64 clusters).
formats::ProbeVolume prepare_for_memory_update(formats::ProbeVolume volume, const MemoryPools& pools,
                                               SeatRoom seats = {});

// invalid_argument naming the first input out of range; ok otherwise.
Status check_frame_inputs(const FrameInputs& inputs);

// An octree node as its depth and integer coordinates at that depth: how a seat's stencils name probes
// (SEAT_STENCIL_VEC4S).
struct NodeKey {
  int x = 0, y = 0, z = 0, depth = 0;
};

class MemoryUpdatePass {
public:
  // `prepared` is what `volume` was uploaded from (prepare_for_memory_update); `trace_flags` and
  // `light_list` are the light update's (LightUpdatePass::trace_flags, light_list). `seat_ints`: with
  // streaming, the frame buffer's room for the arrivals' seat data (at most MEMORY_SEAT_INTS; 0 without),
  // and `cells_file` the file whose subtree of every cell record an arriving cell gets back, with the bake's
  // SVO stencils that name its probes (memory_cells).
  MemoryUpdatePass(Device& device, const GpuVolume& volume, const formats::ProbeVolume& prepared, VkBuffer trace_flags,
                   VkBuffer light_list, std::uint32_t rings, std::uint32_t seat_ints = 0,
                   const formats::ProbeVolume* cells_file = nullptr);

  // Records the frame's inputs (MemoryFrame, and VolumeInfo when a threshold changes) and the memory update
  // with the SVO refresh, ending with its writes visible to later compute and transfer work.
  // `moved_boxes` (the moved objects' old and new bounds) count as changed boxes after inputs.changed_boxes.
  void record_memory_update(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t slot, const FrameInputs& inputs,
                            std::span<const Box> moved_boxes);
  // Records the light transitions (after the probe index build) and the light list's dispatch sizes, ending
  // with their writes visible to compute work and indirect dispatches.
  void record_light_transitions(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t slot);
  // Records the end of the frame: entry states from keys, pool use, counters copied for the host.
  void record_end_of_frame(VkCommandBuffer cmd, std::uint32_t ring);
  // After the submission: this frame's statistics.
  MemoryUpdateStats stats(std::uint32_t ring) const; // of the frame recorded into `ring`, once it finished
  const gpu::VolumeInfo& info() const { return info_; }
  // Streaming: the child word of a cell that is out; a measure whose lattice crosses one decides nothing.
  void set_null_leaf(std::uint32_t word) { null_leaf_ = word; }
  // Streaming: cells arrived; the next memory update queues again the leaves and parents whose measures
  // crossed a cell that was out (memory_remeasure).
  void remeasure_unresolved() { remeasure_ = true; }
  // Streaming: cells (CellStreaming::take_tree_changes: a drop's grid index, or MEMORY_CELL_ARRIVED with
  // an arrival's cell record) whose subtrees the next memory updates give back to the pools or seat again,
  // at most MEMORY_MAX_CELL_CHANGES and MEMORY_SEAT_INTS of seats a frame (the rest wait, in order).
  void change_cells(std::span<const std::uint32_t> changes);

private:
  void dispatch(VkCommandBuffer cmd, VkPipeline pipeline, std::uint32_t threads, std::uint32_t group_size) const;
  // Dispatches the sizes memory_begin wrote at `offset` of the state buffer (as many as there are entries).
  void dispatch_indirect(VkCommandBuffer cmd, VkPipeline pipeline, VkDeviceSize offset) const;
  // memory_begin: the one-thread step whose writes include dispatch sizes.
  void begin(VkCommandBuffer cmd, VkPipeline pipeline) const;
  // The volume set, the pass's set and `push` for the kernels that follow.
  void bind(VkCommandBuffer cmd, const gpu::MemoryPush& push) const;

  Device& device_;
  const GpuVolume& volume_;
  gpu::VolumeInfo info_{}; // as on the GPU (thresholds changed by FrameInputs)
  int batches_per_probe_ = 0;
  std::uint32_t segment_capacity_ = 0;
  std::uint32_t null_leaf_ = 0; // MemoryFrame::null_leaf
  bool remeasure_ = false;
  // The file's subtree below a cell's node, as CellSeat describes it (words and probes local to it).
  struct SeatPayload {
    gpu::CellSeat seat{};
    std::vector<std::int32_t> words; // 9 per cluster
    std::vector<gpu::Probe> probes;
    std::vector<std::int32_t> svo; // the SVO leaves whose bake stencils name the cell's probes: CellSeat::first_svo
    std::size_t ints() const { return words.size() + probes.size() * gpu::SEAT_PROBE_INTS + svo.size(); }
  };
  // This frame's cell changes into `frame` and the seat data (ints behind MemoryFrame); takes them from
  // cell_changes_ while they fit. Returns the arrivals (seats).
  std::size_t take_cell_changes(gpu::MemoryFrame& frame, std::vector<std::int32_t>& seat_data);
  void set_cell_seats(const formats::ProbeVolume& file); // each cell record's subtree as the file has it
  void add_seat_stencils(const formats::ProbeVolume& file, const std::vector<NodeKey>& keys);

  int cell_depth_ = 0;
  std::size_t seat_ints_ = 0;               // room for seat data behind MemoryFrame (streaming)
  std::vector<SeatPayload> seats_;          // per cell record
  std::vector<std::uint32_t> cell_changes_; // not yet given to a frame, oldest first
  Buffer state_, free_stacks_, work_, merge_sh_, marks_, frame_, probe_generations_, svo_generations_, svo_bake_;
  PassCounters<gpu::MemoryCounters> counters_;
  PassDescriptorSet descriptors_;
};

} // namespace probebake::runtime::detail
