#include "pipelines.h"

#include <string>
#include <vector>

#include "error.h"
#include "handles.h"
#include "probebake/memory_types.h"
#include "probebake/runtime_types.h"
#include "probebake/shader_library.h"

namespace probebake::runtime::detail {
namespace {

// One push-constant block per pass layout, of the size of its Push struct (runtime_types.h, memory_types.h).
PassLayout make_pass_layout(VkDevice device, std::uint32_t bindings, std::uint32_t push_bytes) {
  std::vector<VkDescriptorSetLayoutBinding> entries(bindings);
  for (std::uint32_t i = 0; i < bindings; ++i)
    entries[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  auto set_info = vk_struct<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  set_info.bindingCount = bindings;
  set_info.pBindings = entries.data();
  PassLayout pass;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  check_vk(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
  pass.set_layout = DeviceObject<VkDescriptorSetLayout>(device, set_layout, vkDestroyDescriptorSetLayout);

  const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  auto layout_info = vk_struct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &set_layout;
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

Pipelines::Pipelines(VkDevice device) {
  probe_index = make_pass_layout(device, gpu::PROBE_INDEX_BINDING_COUNT, sizeof(gpu::ProbeIndexPush));
  probe_index_count = make_pipeline(device, probe_index.layout.get(), "probe_index_count");
  probe_index_scan = make_pipeline(device, probe_index.layout.get(), "probe_index_scan");
  probe_index_scatter = make_pipeline(device, probe_index.layout.get(), "probe_index_scatter");
  sample = make_pass_layout(device, gpu::SAMPLE_BINDING_COUNT, sizeof(gpu::SamplePush));
  sample_irradiance = make_pipeline(device, sample.layout.get(), "sample_irradiance");
  sample_all = make_pass_layout(device, gpu::SAMPLE_ALL_BINDING_COUNT, sizeof(gpu::SamplePush));
  sample_all_probes = make_pipeline(device, sample_all.layout.get(), "sample_all_probes");
  light = make_pass_layout(device, gpu::LIGHT_BINDING_COUNT, sizeof(gpu::LightPush));
  light_trace = make_pipeline(device, light.layout.get(), "light_trace");
  light_trace_list = make_pipeline(device, light.layout.get(), "light_trace_list");
  light_gather = make_pipeline(device, light.layout.get(), "light_gather");
  light_resolve = make_pipeline(device, light.layout.get(), "light_resolve");
  light_relight = make_pipeline(device, light.layout.get(), "light_relight");
  light_mark_stale = make_pipeline(device, light.layout.get(), "light_mark_stale");
  light_mark_moved = make_pipeline(device, light.layout.get(), "light_mark_moved");
  memory = make_pass_layout(device, gpu::MEMORY_BINDING_COUNT, sizeof(gpu::MemoryPush));
  memory_begin = make_pipeline(device, memory.layout.get(), "memory_begin");
  memory_decide = make_pipeline(device, memory.layout.get(), "memory_decide");
  memory_release = make_pipeline(device, memory.layout.get(), "memory_release");
  memory_grant = make_pipeline(device, memory.layout.get(), "memory_grant");
  memory_allocate = make_pipeline(device, memory.layout.get(), "memory_allocate");
  memory_collapse = make_pipeline(device, memory.layout.get(), "memory_collapse");
  memory_remeasure = make_pipeline(device, memory.layout.get(), "memory_remeasure");
  memory_cells = make_pipeline(device, memory.layout.get(), "memory_cells");
  memory_svo = make_pipeline(device, memory.layout.get(), "memory_svo");
  memory_light = make_pipeline(device, memory.layout.get(), "memory_light");
  memory_sync = make_pipeline(device, memory.layout.get(), "memory_sync");
  object = make_pass_layout(device, gpu::OBJECT_BINDING_COUNT, sizeof(gpu::ObjectRefitPush));
  object_refit = make_pipeline(device, object.layout.get(), "object_refit");
  stream = make_pass_layout(device, gpu::STREAM_BINDING_COUNT, sizeof(gpu::StreamRelocatePush));
  stream_relocate = make_pipeline(device, stream.layout.get(), "stream_relocate");
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
