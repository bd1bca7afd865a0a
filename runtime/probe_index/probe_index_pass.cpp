#include "probe_index/probe_index_pass.h"

#include <algorithm>
#include <array>
#include <string>

#include "core/error.h"
#include "core/pipelines.h"
#include "probe_index/probe_index_bindings.h"
#include "probebake/runtime_types.h"

namespace probebake::runtime::detail {
namespace {

constexpr VkBufferUsageFlags kScratchUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
// The reset value: every int32 of the list becomes PROBE_INDEX_END (-1, all bits set).
constexpr std::uint32_t kIndexEndBits = static_cast<std::uint32_t>(gpu::PROBE_INDEX_END);
static_assert(gpu::PROBE_INDEX_END == -1 && kIndexEndBits == 0xffffffffu);

// Writes into the build's scratch and counters before they are read by the next step, and the list's reset
// (a transfer) before the scatter writes it.
constexpr Access kFillOrComputeWrite{VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                     VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT};

} // namespace

ProbeIndexPass::ProbeIndexPass(Device& device, const GpuVolume& volume, std::uint32_t rings)
    : device_(device), volume_(volume) {
  probe_capacity_ = static_cast<std::uint32_t>(volume.elements(Section::probes));
  if (volume.elements(Section::probe_index) != std::size_t(probe_capacity_) + 1)
    fail(StatusCode::invalid_volume,
         "probe_index: " + std::to_string(volume.elements(Section::probe_index)) +
             " elements, expected probe capacity + 1 = " + std::to_string(probe_capacity_ + 1ull));
  block_count_ = (probe_capacity_ + gpu::PROBE_INDEX_BLOCK - 1) / gpu::PROBE_INDEX_BLOCK;
  const VkDeviceSize sums_bytes = VkDeviceSize(std::max<std::uint32_t>(block_count_, 1)) * sizeof(std::uint32_t);
  block_sums_ = device.allocator->create_buffer(sums_bytes, kScratchUsage, MemoryUse::device, "probe index block sums");
  counters_ = PassCounters<gpu::RuntimeCounters>(device, "runtime counters", rings);
  std::array<VkBuffer, gpu::PROBE_INDEX_BINDING_COUNT> buffers{};
  buffers[gpu::PROBE_INDEX_BINDING_BLOCK_SUMS] = block_sums_.get();
  buffers[gpu::PROBE_INDEX_BINDING_COUNTERS] = counters_.buffer();
  descriptors_ =
      make_pass_descriptor_set(device.vk(), device.compute_pipelines().set_layout(Layout::probe_index), buffers);
}

void ProbeIndexPass::record(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t timer_slot) const {
  Pipelines& pipelines = device_.compute_pipelines();
  const VkPipelineLayout layout = pipelines.layout(Layout::probe_index);
  const gpu::ProbeIndexPush push{probe_capacity_, block_count_, 0, 0};
  timer.begin(cmd, timer_slot);
  // 1. Reset the list to PROBE_INDEX_END (thesis §3.2.3: "resetting all indices ... to an invalid index").
  vkCmdFillBuffer(cmd, volume_.buffer(Section::probe_index).get(), 0, VK_WHOLE_SIZE, kIndexEndBits);
  bind_sets_and_push(cmd, layout, volume_.volume_set(), descriptors_.set, push);
  // 2. Allocated probes per block.
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.kernel(Kernel::probe_index_count));
  dispatch_groups(cmd, device_, block_count_);
  barrier(cmd, kComputeWrite, kComputeReadWrite);
  // 3. Exclusive offsets of the blocks and the live count (one workgroup).
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.kernel(Kernel::probe_index_scan));
  vkCmdDispatch(cmd, 1, 1, 1);
  barrier(cmd, kFillOrComputeWrite, kComputeReadWrite);
  // 4. Insert every allocated probe at its block offset + rank in the block: ascending order.
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.kernel(Kernel::probe_index_scatter));
  dispatch_groups(cmd, device_, block_count_);
  timer.end(cmd, timer_slot);
  // The list is read by later passes (and the next frame's reset waits on the frame-start barrier).
  counters_.record_end_of_pass_copy(cmd, timer.ring());
}

int ProbeIndexPass::live_probes(std::uint32_t ring) const { return counters_.read(ring).live_probes; }

} // namespace probebake::runtime::detail
