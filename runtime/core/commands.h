// Command recording helpers: a one-time command buffer submitted and waited for with a fence, global
// memory barriers (Vulkan 1.2 vkCmdPipelineBarrier; a VkMemoryBarrier covers every buffer, which is what
// compute passes over many buffers need), and per-pass GPU timestamps.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "core/device.h"
#include "core/handles.h"

namespace probebake::runtime::detail {

class Submission {
public:
  explicit Submission(Device& device); // allocates a primary command buffer and begins it
  Submission(const Submission&) = delete;
  Submission& operator=(const Submission&) = delete;
  ~Submission();

  VkCommandBuffer cmd() const { return cmd_; }
  // Ends, submits and waits (too_slow after 60 s). Call once.
  void submit_and_wait();

private:
  Device& device_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
};

struct Access {
  VkPipelineStageFlags stages;
  VkAccessFlags access;
};
inline constexpr Access kComputeWrite{VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT};
inline constexpr Access kComputeRead{VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT};
inline constexpr Access kComputeReadWrite{VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT};
// Compute shaders and the indirect dispatch sizes they are launched with (the light list, the memory state).
inline constexpr Access kComputeAndIndirect{VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                                            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                                                VK_ACCESS_INDIRECT_COMMAND_READ_BIT};
inline constexpr Access kTransferWrite{VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT};
inline constexpr Access kTransferRead{VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT};
inline constexpr Access kHostRead{VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT};
// Everything the runtime does to its buffers on the device: used at frame and submission boundaries.
inline constexpr Access kAnyDeviceAccess{VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                                         VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                                             VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT};

// Any command of the host recorded around a frame, in any stage (valid on compute-only queues too): what came
// before (its reads of the volume; the runtime's own writes) and the reads that follow.
inline constexpr Access kAnyCommandBefore{VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, kAnyDeviceAccess.access};
inline constexpr Access kAnyCommandReadAfter{VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                                             VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT};

// Global memory barrier: `before` accesses happen before and are visible to `after` accesses.
void barrier(VkCommandBuffer cmd, Access before, Access after);

// Dispatches `groups` workgroups split over x and y (shaders use probebake_flat_workgroup()); extra
// groups in the last row must return early (the shaders check their counts).
void dispatch_groups(VkCommandBuffer cmd, const Device& device, std::uint32_t groups, std::uint32_t z = 1);

// Begin/end timestamps of named passes; without timestamp support every time is -1. `rings` sets of
// queries, one per frame in flight: a frame records into ring r while earlier frames' rings are still
// pending on the GPU, and their times are read once they finished.
class PassTimer {
public:
  PassTimer(Device& device, std::uint32_t max_passes, std::uint32_t rings = 1);
  // Call before the first pass in a command buffer: resets ring `ring`'s queries, which the following
  // begin/end calls write.
  void reset(VkCommandBuffer cmd, std::uint32_t ring = 0);
  std::uint32_t ring() const { return ring_; } // the ring being recorded
  void begin(VkCommandBuffer cmd, std::uint32_t pass);
  void end(VkCommandBuffer cmd, std::uint32_t pass);
  // After the command buffer completed: ms per pass for passes [0, passes) of ring 0, all recorded.
  std::vector<double> read_ms(std::uint32_t passes) const;
  // The same for one recorded pass of a ring (a frame skips some passes; their queries stay unavailable).
  double read_pass_ms(std::uint32_t pass, std::uint32_t ring = 0) const;

private:
  std::uint32_t query(std::uint32_t ring, std::uint32_t pass) const { return 2 * (ring * max_passes_ + pass); }
  Device& device_;
  std::uint32_t max_passes_;
  std::uint32_t rings_;
  std::uint32_t ring_ = 0;
  DeviceObject<VkQueryPool> pool_;
};

} // namespace probebake::runtime::detail
