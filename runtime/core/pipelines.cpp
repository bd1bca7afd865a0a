#include "core/pipelines.h"

#include <iterator>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/shader_library.h"
#include "pass_bindings.h"
#include "probebake/memory_types.h"
#include "probebake/runtime_types.h"

namespace probebake::runtime::detail {
namespace {

DeviceObject<VkDescriptorSetLayout> make_set_layout(VkDevice device, std::uint32_t bindings) {
  std::vector<VkDescriptorSetLayoutBinding> entries(bindings);
  for (std::uint32_t i = 0; i < bindings; ++i)
    entries[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  auto info = vk_struct<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  info.bindingCount = bindings;
  info.pBindings = entries.data();
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  check_vk(vkCreateDescriptorSetLayout(device, &info, nullptr, &layout), "vkCreateDescriptorSetLayout");
  return DeviceObject<VkDescriptorSetLayout>(device, layout, vkDestroyDescriptorSetLayout);
}

// Set 0 the volume set, set 1 the pass's own buffers (none: an empty set layout keeps set numbers the
// same in every layout), one push-constant block of the size of its Push struct.
PassLayout make_pass_layout(VkDevice device, VkDescriptorSetLayout volume_set, std::uint32_t bindings,
                            std::uint32_t push_bytes) {
  PassLayout pass;
  pass.set_layout = make_set_layout(device, bindings);
  const VkDescriptorSetLayout sets[2] = {volume_set, pass.set_layout.get()};
  const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  auto layout_info = vk_struct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  layout_info.setLayoutCount = 2;
  layout_info.pSetLayouts = sets;
  layout_info.pushConstantRangeCount = 1;
  layout_info.pPushConstantRanges = &push;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  check_vk(vkCreatePipelineLayout(device, &layout_info, nullptr, &layout), "vkCreatePipelineLayout");
  pass.layout = DeviceObject<VkPipelineLayout>(device, layout, vkDestroyPipelineLayout);
  return pass;
}

DeviceObject<VkPipeline> make_pipeline(VkDevice device, VkPipelineLayout layout, std::string_view shader) {
  const std::span<const std::uint32_t> words = shaders::spirv(shader);
  if (words.empty()) fail(StatusCode::internal, "no embedded SPIR-V for shader " + std::string(shader));
  auto module_info = vk_struct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  module_info.codeSize = words.size_bytes();
  module_info.pCode = words.data();
  VkShaderModule raw_module = VK_NULL_HANDLE;
  check_vk(vkCreateShaderModule(device, &module_info, nullptr, &raw_module), "vkCreateShaderModule");
  const DeviceObject<VkShaderModule> module(device, raw_module, vkDestroyShaderModule);

  auto info = vk_struct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  info.stage = vk_struct<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module.get();
  info.stage.pName = "main";
  info.layout = layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  check_vk(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
           ("vkCreateComputePipelines " + std::string(shader)).c_str());
  return DeviceObject<VkPipeline>(device, pipeline, vkDestroyPipeline);
}

} // namespace

// The pass table's rows: each layout's set-1 binding count and push size, each kernel's name and layout.
struct LayoutRow {
  std::uint32_t bindings, push_bytes;
};
constexpr LayoutRow kLayoutRows[] = {
#define PROBEBAKE_LAYOUT(name, push, bindings) {gpu::bindings, sizeof(gpu::push)},
#include "probebake/runtime/passes.def"
};
struct KernelRow {
  const char* name;
  Layout layout;
};
constexpr KernelRow kKernelRows[] = {
#define PROBEBAKE_KERNEL(folder, name, layout) {#name, Layout::layout},
#include "probebake/runtime/passes.def"
};
static_assert(std::size(kLayoutRows) == kLayoutCount && std::size(kKernelRows) == kKernelCount);
// Every layout's two sets fit the storage buffers a kernel may see on lavapipe (maxPerStageDescriptorStorageBuffers
// 32; desktop GPUs allow far more), which the validation layers would otherwise report at pipeline creation.
constexpr bool layouts_fit_lavapipe() {
  for (const LayoutRow& row : kLayoutRows)
    if (gpu::VOLUME_BINDING_COUNT + row.bindings > 32) return false;
  return true;
}
static_assert(layouts_fit_lavapipe(), "a pipeline layout has more than 32 storage buffers");

Pipelines::Pipelines(VkDevice device) {
  volume_set_layout_ = make_set_layout(device, gpu::VOLUME_BINDING_COUNT);
  for (std::size_t i = 0; i < kLayoutCount; ++i)
    layouts_[i] =
        make_pass_layout(device, volume_set_layout_.get(), kLayoutRows[i].bindings, kLayoutRows[i].push_bytes);
  for (std::size_t i = 0; i < kKernelCount; ++i)
    kernels_[i] = make_pipeline(device, layout(kKernelRows[i].layout), kKernelRows[i].name);
}

DeviceObject<VkDescriptorPool> make_descriptor_pool(VkDevice device, std::uint32_t sets,
                                                    std::uint32_t buffers_per_set) {
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, sets * buffers_per_set};
  auto info = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  info.maxSets = sets;
  info.poolSizeCount = 1;
  info.pPoolSizes = &size;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  check_vk(vkCreateDescriptorPool(device, &info, nullptr, &pool), "vkCreateDescriptorPool");
  return DeviceObject<VkDescriptorPool>(device, pool, vkDestroyDescriptorPool);
}

VkDescriptorSet allocate_set(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout) {
  auto info = vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  info.descriptorPool = pool;
  info.descriptorSetCount = 1;
  info.pSetLayouts = &layout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  check_vk(vkAllocateDescriptorSets(device, &info, &set), "vkAllocateDescriptorSets");
  return set;
}

PassDescriptorSet make_pass_descriptor_set(VkDevice device, VkDescriptorSetLayout layout,
                                           std::span<const VkBuffer> buffers) {
  PassDescriptorSet out;
  out.pool = make_descriptor_pool(device, 1, static_cast<std::uint32_t>(buffers.size()));
  out.set = allocate_set(device, out.pool.get(), layout);
  write_storage_buffers(device, out.set, buffers);
  return out;
}

void write_storage_buffers(VkDevice device, VkDescriptorSet set, std::span<const VkBuffer> buffers) {
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    infos[i] = {buffers[i], 0, VK_WHOLE_SIZE};
    writes[i] = vk_struct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    writes[i].dstSet = set;
    writes[i].dstBinding = static_cast<std::uint32_t>(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(device, static_cast<std::uint32_t>(writes.size()), writes.data(), 0, nullptr);
}

} // namespace probebake::runtime::detail
