#include "core/device.h"

#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/handles.h"
#include "core/pipelines.h"

namespace probebake::runtime::detail {
namespace {

const char* type_name(VkPhysicalDeviceType type) {
  switch (type) {
  case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
  case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
  case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
  case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
  default: return "other";
  }
}

// Lower is better: discrete GPUs first, CPU implementations (lavapipe) last.
int type_rank(VkPhysicalDeviceType type) {
  switch (type) {
  case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
  case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
  case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
  case VK_PHYSICAL_DEVICE_TYPE_CPU: return 4;
  default: return 3;
  }
}

std::vector<VkQueueFamilyProperties> queue_families(VkPhysicalDevice device) {
  std::uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  return families;
}

// A compute family, preferring one with timestamps; -1 when there is none.
int compute_family(VkPhysicalDevice device) {
  const auto families = queue_families(device);
  int best = -1;
  for (std::size_t i = 0; i < families.size(); ++i) {
    if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) || families[i].queueCount == 0) continue;
    if (families[i].timestampValidBits > 0) return static_cast<int>(i);
    if (best < 0) best = static_cast<int>(i);
  }
  return best;
}

struct Candidate {
  VkPhysicalDevice device = VK_NULL_HANDLE;
  int family = -1;
  int rank = 1 << 30;
};

Candidate pick_physical_device(VkInstance instance, const std::string& name_filter) {
  std::uint32_t count = 0;
  check_vk(vkEnumeratePhysicalDevices(instance, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  check_vk(vkEnumeratePhysicalDevices(instance, &count, devices.data()), "vkEnumeratePhysicalDevices");
  Candidate best;
  std::string seen;
  for (VkPhysicalDevice device : devices) {
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(device, &properties);
    seen += std::string(seen.empty() ? "" : ", ") + properties.deviceName;
    const int family = compute_family(device);
    if (properties.apiVersion < VK_API_VERSION_1_2 || family < 0) continue;
    if (!name_filter.empty() && std::string(properties.deviceName).find(name_filter) == std::string::npos) continue;
    const int rank = type_rank(properties.deviceType);
    if (rank < best.rank) best = {device, family, rank};
  }
  if (best.device == VK_NULL_HANDLE)
    fail(StatusCode::no_device, "no Vulkan 1.2 device with a compute queue" +
                                    (name_filter.empty() ? std::string() : " named like \"" + name_filter + "\"") +
                                    " (devices: " + (seen.empty() ? "none" : seen) + ")");
  return best;
}

void describe(Device& d, bool borrowed, std::uint64_t range_limit) {
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(d.physical_device, &properties);
  if (properties.apiVersion < VK_API_VERSION_1_2) fail(StatusCode::no_device, "the device does not support Vulkan 1.2");
  const auto families = queue_families(d.physical_device);
  if (d.queue_family >= families.size() || !(families[d.queue_family].queueFlags & VK_QUEUE_COMPUTE_BIT))
    fail(StatusCode::invalid_argument, "queue family " + std::to_string(d.queue_family) + " has no compute support");
  d.limits = properties.limits;
  d.timestamp_valid_bits = families[d.queue_family].timestampValidBits;
  d.info.name = properties.deviceName;
  d.info.type = type_name(properties.deviceType);
  d.info.api_version = properties.apiVersion;
  d.info.max_storage_buffer_range = properties.limits.maxStorageBufferRange;
  if (range_limit > 0) d.info.max_storage_buffer_range = std::min(d.info.max_storage_buffer_range, range_limit);
  d.info.timestamps = d.timestamp_valid_bits > 0 && properties.limits.timestampPeriod > 0.0f;
  d.info.borrowed = borrowed;
  d.info.validation = d.instance.validation();
}

void create_pool_and_allocator(Device& d) {
  d.allocator = std::make_unique<Allocator>(d.physical_device, d.vk());
  auto pool = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = d.queue_family;
  VkCommandPool raw = VK_NULL_HANDLE;
  check_vk(vkCreateCommandPool(d.vk(), &pool, nullptr, &raw), "vkCreateCommandPool");
  d.command_pool = DeviceObject<VkCommandPool>(d.vk(), raw, vkDestroyCommandPool);
}

} // namespace

Device::Device(std::shared_ptr<MessageLog> message_log, Instance vk_instance)
    : log(std::move(message_log)), instance(std::move(vk_instance)) {}

Device::~Device() {
  // Every submission of the runtime is waited for before its call returns; an owned device is idled anyway
  // before its objects go (a borrowed queue is the host's, so it is not touched here).
  if (device.owned() && device.get() != VK_NULL_HANDLE) vkDeviceWaitIdle(device.get());
}

Pipelines& Device::compute_pipelines() {
  if (!pipelines) pipelines = std::make_unique<Pipelines>(vk());
  return *pipelines;
}

std::shared_ptr<Device> create_device(const ContextOptions& options) {
  auto log = std::make_shared<MessageLog>(options.on_validation_message);
  auto d = std::make_shared<Device>(log, Instance::create(options.validation, log));
  const Candidate candidate = pick_physical_device(d->instance.get(), options.device_name_contains);
  d->physical_device = candidate.device;
  d->queue_family = static_cast<std::uint32_t>(candidate.family);

  const float priority = 1.0f;
  auto queue = vk_struct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queue.queueFamilyIndex = d->queue_family;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  auto info = vk_struct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue;
  VkDevice raw = VK_NULL_HANDLE;
  check_vk(vkCreateDevice(d->physical_device, &info, nullptr, &raw), "vkCreateDevice");
  d->device = LogicalDevice(raw, true);
  vkGetDeviceQueue(d->vk(), d->queue_family, 0, &d->queue);
  describe(*d, false, options.storage_buffer_range_limit);
  create_pool_and_allocator(*d);
  return d;
}

std::shared_ptr<Device> borrow_device(const HostVulkan& host, const ContextOptions& options) {
  if (!host.instance || !host.physical_device || !host.device || !host.queue)
    fail(StatusCode::invalid_argument, "Context::borrow: instance, physical device, device and queue must be given");
  auto d = std::make_shared<Device>(std::make_shared<MessageLog>(nullptr), Instance::borrow(host.instance));
  d->physical_device = host.physical_device;
  d->device = LogicalDevice(host.device, false);
  d->queue = host.queue;
  d->queue_family = host.queue_family_index;
  describe(*d, true, options.storage_buffer_range_limit);
  create_pool_and_allocator(*d);
  return d;
}

} // namespace probebake::runtime::detail
