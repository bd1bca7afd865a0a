// consumer FILE.probes: what a game does with an installed probebake (tests/consumer/CMakeLists.txt).
// Creates its own Vulkan instance, device and queue, lends them to the runtime (Context::borrow), loads the
// volume and runs a few frames of its passes, then samples irradiance in its own compute shader
// (game_sample.comp, compiled against the installed GLSL includes), recorded into its own command buffer
// with its own descriptor sets bound to Volume::buffers(). Exit 0 when the game's values equal the
// runtime's own sampling pass (Volume::sample_irradiance) at every point, 1 otherwise; then the same with the
// compact l2 probes (UploadOptions::probe_code), the records' binding holding a 16-byte dummy that the shader
// must not read. With --validation the
// game's instance enables VK_LAYER_KHRONOS_validation with synchronization validation, and any message fails.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "game_sample.spv.h"
#include "game_sample_l2.spv.h"
#include "probebake/runtime/runtime.h"

namespace {

void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed: VkResult " + std::to_string(result));
}

int validation_messages = 0;

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                          const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  ++validation_messages;
  std::fprintf(stderr, "consumer: validation: %s\n", data->pMessage);
  return VK_FALSE;
}

// The game's own Vulkan objects: destroyed after the runtime's (the runtime borrows them).
struct GameVulkan {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t family = 0;

  explicit GameVulkan(bool validation) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "probebake consumer";
    app.apiVersion = VK_API_VERSION_1_2;
    const char* layer = "VK_LAYER_KHRONOS_validation";
    const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    const VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = &sync;
    VkDebugUtilsMessengerCreateInfoEXT messenger_info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messenger_info.pNext = &features;
    messenger_info.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                 VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                 VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger_info.pfnUserCallback = on_message;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    if (validation) {
      info.pNext = &messenger_info;
      info.enabledLayerCount = 1;
      info.ppEnabledLayerNames = &layer;
      info.enabledExtensionCount = 1;
      info.ppEnabledExtensionNames = &extension;
    }
    check(vkCreateInstance(&info, nullptr, &instance), "vkCreateInstance");
    if (validation) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
      messenger_info.pNext = nullptr;
      check(create ? create(instance, &messenger_info, nullptr, &messenger) : VK_ERROR_EXTENSION_NOT_PRESENT,
            "vkCreateDebugUtilsMessengerEXT");
    }
    std::uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance, &count, devices.data());
    for (VkPhysicalDevice candidate : devices) {
      VkPhysicalDeviceProperties props;
      vkGetPhysicalDeviceProperties(candidate, &props);
      if (props.apiVersion < VK_API_VERSION_1_2) continue;
      std::uint32_t families = 0;
      vkGetPhysicalDeviceQueueFamilyProperties(candidate, &families, nullptr);
      std::vector<VkQueueFamilyProperties> family_props(families);
      vkGetPhysicalDeviceQueueFamilyProperties(candidate, &families, family_props.data());
      for (std::uint32_t f = 0; f < families && physical == VK_NULL_HANDLE; ++f)
        if (family_props[f].queueFlags & VK_QUEUE_COMPUTE_BIT) physical = candidate, family = f;
      if (physical != VK_NULL_HANDLE) break;
    }
    if (physical == VK_NULL_HANDLE) throw std::runtime_error("no Vulkan 1.2 device with a compute queue");
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue_info.queueFamilyIndex = family;
    queue_info.queueCount = 1;
    queue_info.pQueuePriorities = &priority;
    VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    device_info.queueCreateInfoCount = 1;
    device_info.pQueueCreateInfos = &queue_info;
    check(vkCreateDevice(physical, &device_info, nullptr, &device), "vkCreateDevice");
    vkGetDeviceQueue(device, family, 0, &queue);
  }
  ~GameVulkan() {
    if (device) vkDestroyDevice(device, nullptr);
    if (messenger) {
      auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
      if (destroy) destroy(instance, messenger, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
  }
  GameVulkan(const GameVulkan&) = delete;
  GameVulkan& operator=(const GameVulkan&) = delete;
};

// A host-visible storage buffer the game fills and reads.
struct HostBuffer {
  VkDevice device;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
  VkDeviceSize size;

  HostBuffer(const GameVulkan& vk, VkDeviceSize bytes) : device(vk.device), size(bytes) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    check(vkCreateBuffer(device, &info, nullptr, &buffer), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, buffer, &req);
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(vk.physical, &props);
    const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    std::uint32_t type = props.memoryTypeCount;
    for (std::uint32_t t = 0; t < props.memoryTypeCount && type == props.memoryTypeCount; ++t)
      if ((req.memoryTypeBits & (1u << t)) && (props.memoryTypes[t].propertyFlags & want) == want) type = t;
    if (type == props.memoryTypeCount) throw std::runtime_error("no host-visible coherent memory");
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = type;
    check(vkAllocateMemory(device, &alloc, nullptr, &memory), "vkAllocateMemory");
    check(vkBindBufferMemory(device, buffer, memory, 0), "vkBindBufferMemory");
    check(vkMapMemory(device, memory, 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
  }
  ~HostBuffer() {
    vkDestroyBuffer(device, buffer, nullptr);
    vkFreeMemory(device, memory, nullptr);
  }
  HostBuffer(const HostBuffer&) = delete;
  HostBuffer& operator=(const HostBuffer&) = delete;
  glm::vec4* vec4s() { return static_cast<glm::vec4*>(mapped); }
};

// The game's pipeline: set 0 = its own buffers (points, normals, shaded), set 1 = the volume at 4-7 and, for
// the compact probes' shader, their points and codes at 8-9.
struct GamePipeline {
  VkDevice device;
  VkDescriptorSetLayout layouts[2]{};
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet sets[2]{};

  GamePipeline(VkDevice d, const std::uint32_t* spirv, std::size_t spirv_bytes, std::uint32_t volume_bindings)
      : device(d) {
    for (int s = 0; s < 2; ++s) {
      VkDescriptorSetLayoutBinding bindings[6]{};
      const std::uint32_t count = s == 0 ? 3u : volume_bindings;
      for (std::uint32_t b = 0; b < count; ++b) {
        bindings[b].binding = s == 0 ? b : 4 + b;
        bindings[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        bindings[b].descriptorCount = 1;
        bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
      }
      VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
      info.bindingCount = count;
      info.pBindings = bindings;
      check(vkCreateDescriptorSetLayout(device, &info, nullptr, &layouts[s]), "vkCreateDescriptorSetLayout");
    }
    VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, 4};
    VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout_info.setLayoutCount = 2;
    layout_info.pSetLayouts = layouts;
    layout_info.pushConstantRangeCount = 1;
    layout_info.pPushConstantRanges = &push;
    check(vkCreatePipelineLayout(device, &layout_info, nullptr, &layout), "vkCreatePipelineLayout");
    VkShaderModuleCreateInfo module_info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    module_info.codeSize = spirv_bytes;
    module_info.pCode = spirv;
    VkShaderModule module;
    check(vkCreateShaderModule(device, &module_info, nullptr, &module), "vkCreateShaderModule");
    VkComputePipelineCreateInfo pipeline_info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    pipeline_info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                           nullptr,
                           0,
                           VK_SHADER_STAGE_COMPUTE_BIT,
                           module,
                           "main",
                           nullptr};
    pipeline_info.layout = layout;
    const VkResult made = vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &pipeline);
    vkDestroyShaderModule(device, module, nullptr);
    check(made, "vkCreateComputePipelines");
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3 + volume_bindings};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 2;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &size;
    check(vkCreateDescriptorPool(device, &pool_info, nullptr, &pool), "vkCreateDescriptorPool");
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 2;
    alloc.pSetLayouts = layouts;
    check(vkAllocateDescriptorSets(device, &alloc, sets), "vkAllocateDescriptorSets");
  }
  ~GamePipeline() {
    vkDestroyDescriptorPool(device, pool, nullptr);
    vkDestroyPipeline(device, pipeline, nullptr);
    vkDestroyPipelineLayout(device, layout, nullptr);
    for (VkDescriptorSetLayout l : layouts) vkDestroyDescriptorSetLayout(device, l, nullptr);
  }
  GamePipeline(const GamePipeline&) = delete;
  GamePipeline& operator=(const GamePipeline&) = delete;

  void bind(std::uint32_t set, std::uint32_t binding, VkBuffer buffer) {
    VkDescriptorBufferInfo info{buffer, 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = sets[set];
    write.dstBinding = binding;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    write.pBufferInfo = &info;
    vkUpdateDescriptorSets(device, 1, &write, 0, nullptr);
  }
};

// Records the game's dispatch into its own command buffer, submits it and waits (a game would not wait;
// this test reads the results right away).
void dispatch(const GameVulkan& vk, const GamePipeline& p, std::uint32_t count) {
  VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool_info.queueFamilyIndex = vk.family;
  VkCommandPool pool;
  check(vkCreateCommandPool(vk.device, &pool_info, nullptr, &pool), "vkCreateCommandPool");
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vkAllocateCommandBuffers(vk.device, &alloc, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  // The runtime's frames end with its own barrier and were waited for; the game orders its host writes.
  VkMemoryBarrier host_to_shader{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_HOST_WRITE_BIT,
                                 VK_ACCESS_SHADER_READ_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_HOST_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &host_to_shader, 0,
                       nullptr, 0, nullptr);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout, 0, 2, p.sets, 0, nullptr);
  vkCmdPushConstants(cmd, p.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, 4, &count);
  vkCmdDispatch(cmd, (count + 63) / 64, 1, 1);
  VkMemoryBarrier shader_to_host{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_SHADER_WRITE_BIT,
                                 VK_ACCESS_HOST_READ_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &shader_to_host, 0,
                       nullptr, 0, nullptr);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence;
  check(vkCreateFence(vk.device, &fence_info, nullptr, &fence), "vkCreateFence");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  VkResult done = vkQueueSubmit(vk.queue, 1, &submit, fence);
  if (done == VK_SUCCESS) done = vkWaitForFences(vk.device, 1, &fence, VK_TRUE, UINT64_MAX);
  vkDestroyFence(vk.device, fence, nullptr);
  vkDestroyCommandPool(vk.device, pool, nullptr);
  check(done, "vkQueueSubmit / vkWaitForFences");
}

// Points spread over the root cube's middle (deterministic), normals over the sphere.
struct GamePoints {
  std::vector<glm::vec3> positions, normals;
};
GamePoints game_points(const probebake::gpu::VolumeInfo& info, std::uint32_t count) {
  GamePoints p{std::vector<glm::vec3>(count), std::vector<glm::vec3>(count)};
  for (std::uint32_t i = 0; i < count; ++i) {
    const glm::vec3 u(std::fmod(0.618034f * float(i), 1.0f), std::fmod(0.754878f * float(i), 1.0f),
                      std::fmod(0.569840f * float(i), 1.0f));
    p.positions[i] = info.root_min + info.root_size * (0.25f + 0.5f * u);
    const float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(count), r = std::sqrt(1.0f - z * z),
                a = 2.39996323f * float(i);
    p.normals[i] = glm::vec3(r * std::cos(a), z, r * std::sin(a));
  }
  return p;
}

// Loads the volume (probes as `code`), runs three frames, samples in the game's shader and compares with
// Volume::sample_irradiance. 0 when they agree at every point.
int check_game_shader(const GameVulkan& vk, probebake::runtime::Context& context, const char* file,
                      probebake::formats::ShCodec code) {
  using namespace probebake;
  runtime::UploadOptions options;
  options.probe_code = code;
  auto volume = runtime::Volume::load(context, file, options);
  if (!volume.ok()) throw std::runtime_error("Volume::load: " + volume.status().message);
  for (int frame = 0; frame < 3; ++frame)
    if (auto stats = volume->run_frame(); !stats.ok()) throw std::runtime_error("run_frame: " + stats.status().message);

  constexpr std::uint32_t kPoints = 256;
  const GamePoints p = game_points(volume->info(), kPoints);
  HostBuffer points(vk, kPoints * 16), normal_buffer(vk, kPoints * 16), shaded(vk, kPoints * 16), dummy(vk, 16);
  for (std::uint32_t i = 0; i < kPoints; ++i) {
    points.vec4s()[i] = glm::vec4(p.positions[i], 1.0f);
    normal_buffer.vec4s()[i] = glm::vec4(p.normals[i], 0.0f);
  }
  const bool compact = code != formats::ShCodec::float32;
  GamePipeline pipeline(vk.device, compact ? game_sample_l2_spirv : game_sample_spirv,
                        compact ? sizeof(game_sample_l2_spirv) : sizeof(game_sample_spirv), compact ? 6 : 4);
  pipeline.bind(0, 0, points.buffer);
  pipeline.bind(0, 1, normal_buffer.buffer);
  pipeline.bind(0, 2, shaded.buffer);
  const runtime::VolumeBuffers buffers = volume->buffers();
  pipeline.bind(1, 4, buffers.volume_info.buffer);
  pipeline.bind(1, 5, compact ? dummy.buffer : buffers.probes.buffer); // the compact shader never reads it
  pipeline.bind(1, 6, buffers.svo_nodes.buffer);
  pipeline.bind(1, 7, buffers.svo_leaves.buffer);
  if (compact) {
    pipeline.bind(1, 8, buffers.probe_points.buffer);
    pipeline.bind(1, 9, buffers.probe_codes.buffer);
  }
  dispatch(vk, pipeline, kPoints);

  auto expected = volume->sample_irradiance(p.positions, p.normals);
  if (!expected.ok()) throw std::runtime_error("sample_irradiance: " + expected.status().message);
  double worst = 0.0, mean = 0.0;
  int lit = 0;
  for (std::uint32_t i = 0; i < kPoints; ++i) {
    const glm::vec3 game(shaded.vec4s()[i]), runtime_value = expected.value()[i];
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(game[c])) throw std::runtime_error("non-finite irradiance at point " + std::to_string(i));
      worst = std::max(worst, double(std::abs(game[c] - runtime_value[c])) /
                                  std::max(1e-6, double(std::abs(runtime_value[c]))));
      mean += game[c] / (3.0 * kPoints);
    }
    lit += game.x + game.y + game.z > 0.0f ? 1 : 0;
  }
  std::printf("consumer: %s on %s, %s probes: %u points in the game's shader, %d lit, mean %.4g W/m^2, max relative "
              "difference to Volume::sample_irradiance %.3g, %d validation messages\n",
              file, context.device_info().name.c_str(), std::string(formats::sh_codec_name(code)).c_str(), kPoints, lit,
              mean, worst, validation_messages);
  return worst <= 1e-6 && lit > int(kPoints) / 4 ? 0 : 1;
}

int run(const char* file, bool validation) {
  using namespace probebake;
  GameVulkan vk(validation);
  auto context = runtime::Context::borrow({vk.instance, vk.physical, vk.device, vk.queue, vk.family});
  if (!context.ok()) throw std::runtime_error("Context::borrow: " + context.status().message);
  const int records = check_game_shader(vk, context.value(), file, formats::ShCodec::float32);
  const int compact = check_game_shader(vk, context.value(), file, formats::ShCodec::l2);
  return records == 0 && compact == 0 ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
  const bool validation = argc == 3 && std::strcmp(argv[2], "--validation") == 0;
  if (argc != 2 && !validation) {
    std::fprintf(stderr, "usage: consumer FILE.probes [--validation]\n");
    return 2;
  }
  int status = 1;
  try {
    status = run(argv[1], validation); // every Vulkan object is gone when it returns
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
  }
  return validation_messages == 0 ? status : 1;
}
