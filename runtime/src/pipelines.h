// Compute pipelines of the runtime, built once per device from the embedded SPIR-V (shader_library.h),
// and descriptor helpers. Every pass binds only storage buffers (set 0, bindings 0..n-1, compute stage)
// and one 16-byte push constant block. Binding numbers: shaders/include/probebake/bindings.h.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include <vulkan/vulkan_core.h>

#include "handles.h"
#include "probebake/bindings.h"

namespace probebake::runtime::detail {

struct PassLayout {
  DeviceObject<VkDescriptorSetLayout> set_layout;
  DeviceObject<VkPipelineLayout> layout;
};

class Pipelines {
public:
  explicit Pipelines(VkDevice device); // throws RuntimeError

  PassLayout probe_index;
  DeviceObject<VkPipeline> probe_index_count, probe_index_scan, probe_index_scatter;
  PassLayout sample;
  DeviceObject<VkPipeline> sample_irradiance;
  PassLayout sample_all;
  DeviceObject<VkPipeline> sample_all_probes;
  PassLayout light;
  DeviceObject<VkPipeline> light_trace, light_trace_list, light_gather, light_resolve, light_relight, light_mark_stale,
      light_mark_moved;
  PassLayout memory;
  DeviceObject<VkPipeline> memory_begin, memory_decide, memory_release, memory_grant, memory_allocate, memory_collapse,
      memory_remeasure, memory_cells, memory_svo, memory_light, memory_sync;
  PassLayout object;
  DeviceObject<VkPipeline> object_refit;
  PassLayout stream;
  DeviceObject<VkPipeline> stream_relocate;
};

// A pass's descriptor set in a pool of its own, written once: binding i = the whole of buffers[i].
struct PassDescriptorSet {
  DeviceObject<VkDescriptorPool> pool;
  VkDescriptorSet set = VK_NULL_HANDLE;
};
PassDescriptorSet make_pass_descriptor_set(VkDevice device, VkDescriptorSetLayout layout,
                                           std::span<const VkBuffer> buffers);

// Binds `set` as set 0 and the pass's push constants (every layout here has one 16-byte range).
template <class Push>
void bind_set_and_push(VkCommandBuffer cmd, VkPipelineLayout layout, VkDescriptorSet set, const Push& push) {
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 0, nullptr);
  vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
}

// A pool for `sets` descriptor sets of up to `buffers_per_set` storage buffers each.
DeviceObject<VkDescriptorPool> make_descriptor_pool(VkDevice device, std::uint32_t sets, std::uint32_t buffers_per_set);
VkDescriptorSet allocate_set(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout);
// Binding i of `set` = the whole of buffers[i].
void write_storage_buffers(VkDevice device, VkDescriptorSet set, std::span<const VkBuffer> buffers);

} // namespace probebake::runtime::detail
