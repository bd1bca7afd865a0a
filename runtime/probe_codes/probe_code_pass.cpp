#include "probe_codes/probe_code_pass.h"

#include <algorithm>
#include <array>

#include "probe_codes/probe_codes_bindings.h"
#include "probebake/runtime_types.h"

namespace probebake::runtime::detail {
namespace {

constexpr VkBufferUsageFlags kUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;

} // namespace

ProbeCodePass::ProbeCodePass(Device& device, const GpuVolume& volume, formats::ShCodec codec)
    : device_(device), volume_(volume) {
  probe_capacity_ = static_cast<std::uint32_t>(volume.elements(Section::probes));
  code_bands_ = codec == formats::ShCodec::l2 ? 2u : 1u;
  const VkDeviceSize slots = std::max<VkDeviceSize>(probe_capacity_, 1);
  points_ = device.allocator->create_buffer(slots * sizeof(glm::vec4), kUsage, MemoryUse::device, "probe points");
  codes_ = device.allocator->create_buffer(slots * code_bands_ * sizeof(glm::uvec4), kUsage, MemoryUse::device,
                                           "probe codes");
  std::array<VkBuffer, gpu::PROBE_CODES_BINDING_COUNT> buffers{};
  buffers[gpu::PROBE_CODES_BINDING_POINTS] = points_.get();
  buffers[gpu::PROBE_CODES_BINDING_CODES] = codes_.get();
  descriptors_ =
      make_pass_descriptor_set(device.vk(), device.compute_pipelines().set_layout(Layout::probe_codes), buffers);
}

void ProbeCodePass::record(VkCommandBuffer cmd, PassTimer* timer, std::uint32_t timer_slot) const {
  Pipelines& pipelines = device_.compute_pipelines();
  const gpu::ProbeCodePush push{probe_capacity_, code_bands_, 0, 0};
  if (timer) timer->begin(cmd, timer_slot);
  // The records' last writes (light update, memory update, upload) and the last reads of the codes.
  barrier(cmd, kAnyDeviceAccess, kAnyDeviceAccess);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.kernel(Kernel::probe_encode));
  bind_sets_and_push(cmd, pipelines.layout(Layout::probe_codes), volume_.volume_set(), descriptors_.set, push);
  dispatch_groups(cmd, device_, (probe_capacity_ + gpu::RUNTIME_WORKGROUP_SIZE - 1) / gpu::RUNTIME_WORKGROUP_SIZE);
  if (timer) timer->end(cmd, timer_slot);
}

} // namespace probebake::runtime::detail
