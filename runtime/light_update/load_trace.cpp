// The load trace (light_update_pass.h): the order of the probe slots for UploadOptions::load_focus, and the
// list of the probes a frame traces, the flagged ones and the load window's.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "core/pipelines.h"
#include "light_update/light_update_pass.h"

namespace probebake::runtime::detail {

std::vector<std::int32_t> load_order_nearest(std::span<const gpu::Probe> probes, std::uint32_t capacity,
                                             glm::vec3 focus) {
  std::vector<std::pair<float, std::int32_t>> keyed(capacity);
  for (std::uint32_t s = 0; s < capacity; ++s) {
    const bool live = s < probes.size() && probes[s].link != 0;
    const glm::vec3 d = live ? probes[s].position - focus : glm::vec3(0.0f);
    keyed[s] = {live ? glm::dot(d, d) : std::numeric_limits<float>::infinity(), std::int32_t(s)};
  }
  std::sort(keyed.begin(), keyed.end()); // by distance, then slot: the same order on every run
  std::vector<std::int32_t> order(2 * std::size_t(capacity));
  for (std::uint32_t i = 0; i < capacity; ++i) {
    order[i] = keyed[i].second;
    order[capacity + std::size_t(keyed[i].second)] = std::int32_t(i);
  }
  return order;
}

void LightUpdatePass::record_trace_list(VkCommandBuffer cmd, const gpu::LightPush& push, bool flagged,
                                        std::uint32_t load_window) {
  // The trace's dispatch size and count start from zero (after every earlier access to the header).
  barrier(cmd, kComputeAndIndirect, kTransferWrite);
  vkCmdFillBuffer(cmd, light_list_.get(), offsetof(gpu::LightListHeader, trace_x), 4 * sizeof(std::uint32_t), 0);
  barrier(cmd, kTransferWrite, kComputeReadWrite);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, device_.compute_pipelines().kernel(Kernel::light_trace_list));
  if (flagged && queue_driven_)
    vkCmdDispatchIndirect(cmd, light_list_.get(), offsetof(gpu::LightListHeader, resolve_x)); // a thread per place
  else if (flagged)
    dispatch_groups(cmd, device_, (probe_capacity_ + gpu::RUNTIME_WORKGROUP_SIZE - 1) / gpu::RUNTIME_WORKGROUP_SIZE);
  if (load_window > 0) { // the load trace's window of slots, whatever the list holds; the flagged ones are listed
    if (flagged) barrier(cmd, kComputeReadWrite, kComputeReadWrite); // both append to the trace list
    gpu::LightPush window = push;
    window.trace_mode = gpu::LIGHT_TRACE_UNFLAGGED;
    window.listed = 0u, window.first_slot = untraced_from_, window.slot_count = load_window;
    const VkPipelineLayout layout = device_.compute_pipelines().layout(Layout::light);
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(window), &window);
    dispatch_groups(cmd, device_, (load_window + gpu::RUNTIME_WORKGROUP_SIZE - 1) / gpu::RUNTIME_WORKGROUP_SIZE);
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  }
  barrier(cmd, kComputeWrite, kComputeAndIndirect);
}

} // namespace probebake::runtime::detail
