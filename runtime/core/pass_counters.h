// The counters a pass writes for the host (RuntimeCounters of the probe index build, LightCounters of the
// light update): a device buffer that the pass's shaders bind, and a mapped read-back copy. Both passes end
// the same way: their writes made visible to later passes and to the copy, the copy, the copy made visible
// to the host; read() then gives the values after the submission completed. One host copy per frame in
// flight (ring), so that recording frame N never overwrites what frame N - 1 still has to report.
#pragma once

#include <cstring>
#include <string>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "core/allocator.h"
#include "core/commands.h"
#include "core/device.h"

namespace probebake::runtime::detail {

template <class Counters>
class PassCounters {
public:
  PassCounters() = default;
  // Buffers "<name>" and "<name> (host)". TRANSFER_DST: a pass may zero its counters with vkCmdFillBuffer.
  PassCounters(Device& device, const std::string& name, std::uint32_t rings)
      : device_(device.allocator->create_buffer(sizeof(Counters), kUsage, MemoryUse::device, name)) {
    for (std::uint32_t r = 0; r < rings; ++r)
      host_.push_back(device.allocator->create_buffer(sizeof(Counters), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                      MemoryUse::readback, name + " (host " + std::to_string(r) + ")"));
  }

  VkBuffer buffer() const { return device_.get(); }

  // Records the end of the pass: its compute writes before later passes' compute reads and the copy, then
  // the copy to the host buffer, visible to the host once the submission completed.
  void record_end_of_pass_copy(VkCommandBuffer cmd, std::uint32_t ring) const {
    barrier(cmd, kComputeWrite,
            Access{VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT});
    const VkBufferCopy region{0, 0, sizeof(Counters)};
    vkCmdCopyBuffer(cmd, device_.get(), host_.at(ring).get(), 1, &region);
    barrier(cmd, kTransferWrite, kHostRead);
  }

  // After the submission completed: the counters of the pass recorded into `ring`.
  Counters read(std::uint32_t ring) const {
    Counters counters;
    std::memcpy(&counters, host_.at(ring).mapped(), sizeof(counters));
    return counters;
  }

private:
  static constexpr VkBufferUsageFlags kUsage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  Buffer device_;
  std::vector<Buffer> host_; // one per ring
};

} // namespace probebake::runtime::detail
