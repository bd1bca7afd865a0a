#include "core/commands.h"

#include <algorithm>

#include "core/error.h"
#include "core/handles.h"

namespace probebake::runtime::detail {

// ---- Submission ------------------------------------------------------------------------------------------
Submission::Submission(Device& device) : device_(device) {
  auto info = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  info.commandPool = device.command_pool.get();
  info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  info.commandBufferCount = 1;
  check_vk(vkAllocateCommandBuffers(device.vk(), &info, &cmd_), "vkAllocateCommandBuffers");
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  const VkResult result = vkBeginCommandBuffer(cmd_, &begin);
  if (result != VK_SUCCESS) {
    vkFreeCommandBuffers(device.vk(), device.command_pool.get(), 1, &cmd_);
    check_vk(result, "vkBeginCommandBuffer");
  }
}

Submission::~Submission() { vkFreeCommandBuffers(device_.vk(), device_.command_pool.get(), 1, &cmd_); }

void Submission::submit_and_wait() {
  check_vk(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
  auto fence_info = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  VkFence raw_fence = VK_NULL_HANDLE;
  check_vk(vkCreateFence(device_.vk(), &fence_info, nullptr, &raw_fence), "vkCreateFence");
  const DeviceObject<VkFence> fence(device_.vk(), raw_fence, vkDestroyFence);
  auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd_;
  check_vk(vkQueueSubmit(device_.queue, 1, &submit, fence.get()), "vkQueueSubmit");
  constexpr std::uint64_t kTimeoutNs = 60'000'000'000ull;
  const VkResult waited = vkWaitForFences(device_.vk(), 1, &raw_fence, VK_TRUE, kTimeoutNs);
  if (waited == VK_TIMEOUT) {
    vkDeviceWaitIdle(device_.vk()); // the command buffer and fence must not be in use when they are freed
    fail(StatusCode::too_slow, "the device (" + device_.info.name +
                                   ") did not finish a frame within 60 s; spread the load trace over frames "
                                   "(FrameLimits::max_traced_probes or frame_ms; probebake-run --trace-budget N or "
                                   "--frame-ms MS)");
  }
  check_vk(waited, "vkWaitForFences");
}

// ---- Barriers and dispatch -------------------------------------------------------------------------------
void barrier(VkCommandBuffer cmd, Access before, Access after) {
  auto memory = vk_struct<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  memory.srcAccessMask = before.access;
  memory.dstAccessMask = after.access;
  vkCmdPipelineBarrier(cmd, before.stages, after.stages, 0, 1, &memory, 0, nullptr, 0, nullptr);
}

void dispatch_groups(VkCommandBuffer cmd, const Device& device, std::uint32_t groups, std::uint32_t z) {
  if (groups == 0) return;
  const std::uint32_t max_x = device.limits.maxComputeWorkGroupCount[0];
  const std::uint32_t x = std::min(groups, max_x);
  const std::uint32_t y = (groups + x - 1) / x;
  if (y > device.limits.maxComputeWorkGroupCount[1])
    fail(StatusCode::unsupported, "a dispatch of " + std::to_string(groups) + " workgroups exceeds the device limits");
  vkCmdDispatch(cmd, x, y, z);
}

// ---- PassTimer -------------------------------------------------------------------------------------------
PassTimer::PassTimer(Device& device, std::uint32_t max_passes, std::uint32_t rings)
    : device_(device), max_passes_(max_passes), rings_(std::max(1u, rings)) {
  if (!device.info.timestamps) return;
  auto info = vk_struct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2 * max_passes * rings_;
  VkQueryPool pool = VK_NULL_HANDLE;
  check_vk(vkCreateQueryPool(device.vk(), &info, nullptr, &pool), "vkCreateQueryPool");
  pool_ = DeviceObject<VkQueryPool>(device.vk(), pool, vkDestroyQueryPool);
}

void PassTimer::reset(VkCommandBuffer cmd, std::uint32_t ring) {
  if (ring >= rings_) fail(StatusCode::internal, "PassTimer::reset: ring out of range");
  ring_ = ring;
  if (pool_) vkCmdResetQueryPool(cmd, pool_.get(), query(ring, 0), 2 * max_passes_);
}

void PassTimer::begin(VkCommandBuffer cmd, std::uint32_t pass) {
  if (pool_) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_.get(), query(ring_, pass));
}

void PassTimer::end(VkCommandBuffer cmd, std::uint32_t pass) {
  if (pool_) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_.get(), query(ring_, pass) + 1);
}

std::vector<double> PassTimer::read_ms(std::uint32_t passes) const {
  std::vector<double> ms(passes, -1.0);
  for (std::uint32_t i = 0; i < passes; ++i) ms[i] = read_pass_ms(i);
  return ms;
}

double PassTimer::read_pass_ms(std::uint32_t pass, std::uint32_t ring) const {
  if (!pool_) return -1.0;
  std::uint64_t ticks[2] = {0, 0};
  check_vk(vkGetQueryPoolResults(device_.vk(), pool_.get(), query(ring, pass), 2, sizeof(ticks), ticks,
                                 sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
           "vkGetQueryPoolResults");
  const std::uint32_t bits = device_.timestamp_valid_bits;
  const std::uint64_t mask = bits >= 64 ? ~0ull : (1ull << bits) - 1;
  const std::uint64_t elapsed = ((ticks[1] & mask) - (ticks[0] & mask)) & mask;
  return static_cast<double>(elapsed) * static_cast<double>(device_.limits.timestampPeriod) * 1e-6;
}

} // namespace probebake::runtime::detail
