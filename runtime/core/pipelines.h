// Compute pipelines of the runtime, built once per device from the embedded SPIR-V (shader_library.h) by the
// pass table (probebake/runtime/passes.def), and descriptor helpers. Every kernel binds storage buffers
// only: set 0 is the volume set (probebake/bindings.h), set 1 its pass's own buffers (the layout's
// *_BINDING_COUNT in its concept folder), and one 16-byte push constant block.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include <vulkan/vulkan_core.h>

#include "core/handles.h"

namespace probebake::runtime::detail {

// The pass table's layouts and kernels, in row order.
enum class Layout : std::uint32_t {
#define PROBEBAKE_LAYOUT(name, push, bindings) name,
#include "probebake/runtime/passes.def"
};
enum class Kernel : std::uint32_t {
#define PROBEBAKE_KERNEL(folder, name, layout) name,
#include "probebake/runtime/passes.def"
};
inline constexpr std::size_t kLayoutCount = 0
#define PROBEBAKE_LAYOUT(name, push, bindings) +1
#include "probebake/runtime/passes.def"
    ;
inline constexpr std::size_t kKernelCount = 0
#define PROBEBAKE_KERNEL(folder, name, layout) +1
#include "probebake/runtime/passes.def"
    ;

struct PassLayout {
  DeviceObject<VkDescriptorSetLayout> set_layout; // set 1; null for a layout of no buffers of its own
  DeviceObject<VkPipelineLayout> layout;
};

class Pipelines {
public:
  explicit Pipelines(VkDevice device); // throws RuntimeError

  VkDescriptorSetLayout volume_set_layout() const { return volume_set_layout_.get(); }
  VkDescriptorSetLayout set_layout(Layout layout) const { return layouts_[std::size_t(layout)].set_layout.get(); }
  VkPipelineLayout layout(Layout layout) const { return layouts_[std::size_t(layout)].layout.get(); }
  VkPipeline kernel(Kernel kernel) const { return kernels_[std::size_t(kernel)].get(); }

private:
  DeviceObject<VkDescriptorSetLayout> volume_set_layout_;
  std::array<PassLayout, kLayoutCount> layouts_;
  std::array<DeviceObject<VkPipeline>, kKernelCount> kernels_;
};

// A descriptor set in a pool of its own, written once: binding i = the whole of buffers[i].
struct PassDescriptorSet {
  DeviceObject<VkDescriptorPool> pool;
  VkDescriptorSet set = VK_NULL_HANDLE;
};
PassDescriptorSet make_pass_descriptor_set(VkDevice device, VkDescriptorSetLayout layout,
                                           std::span<const VkBuffer> buffers);

// Binds the volume set (set 0) and, unless null, the pass's set (set 1), and the pass's push constants
// (every layout here has one 16-byte range).
template <class Push>
void bind_sets_and_push(VkCommandBuffer cmd, VkPipelineLayout layout, VkDescriptorSet volume_set,
                        VkDescriptorSet pass_set, const Push& push) {
  const VkDescriptorSet sets[2] = {volume_set, pass_set};
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, pass_set ? 2 : 1, sets, 0, nullptr);
  vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
}
// A kernel that reads nothing of the volume: its set 1 and push constants only.
template <class Push>
void bind_pass_set_and_push(VkCommandBuffer cmd, VkPipelineLayout layout, VkDescriptorSet pass_set, const Push& push) {
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 1, 1, &pass_set, 0, nullptr);
  vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
}

// A pool for `sets` descriptor sets of up to `buffers_per_set` storage buffers each.
DeviceObject<VkDescriptorPool> make_descriptor_pool(VkDevice device, std::uint32_t sets, std::uint32_t buffers_per_set);
VkDescriptorSet allocate_set(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout);
// Binding i of `set` = the whole of buffers[i].
void write_storage_buffers(VkDevice device, VkDescriptorSet set, std::span<const VkBuffer> buffers);

} // namespace probebake::runtime::detail
