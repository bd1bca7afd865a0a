// The device the runtime works on: instance, physical device, logical device, one compute queue, the
// allocator, a command pool and the compute pipelines, owned or borrowed from the host (Context::borrow).
// Shared (std::shared_ptr) by the Context and its Volumes, so it is destroyed after the last of them.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>

#include <vulkan/vulkan_core.h>

#include "core/allocator.h"
#include "core/handles.h"
#include "core/instance.h"
#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

class Pipelines;

// Destroys an owned VkDevice; does nothing for a borrowed one.
class LogicalDevice {
public:
  LogicalDevice() = default;
  LogicalDevice(VkDevice device, bool owned) : device_(device), owned_(owned) {}
  LogicalDevice(const LogicalDevice&) = delete;
  LogicalDevice& operator=(const LogicalDevice&) = delete;
  LogicalDevice& operator=(LogicalDevice&& other) noexcept {
    std::swap(device_, other.device_);
    std::swap(owned_, other.owned_);
    return *this;
  }
  ~LogicalDevice() {
    if (owned_ && device_ != VK_NULL_HANDLE) vkDestroyDevice(device_, nullptr);
  }
  VkDevice get() const { return device_; }
  bool owned() const { return owned_; }

private:
  VkDevice device_ = VK_NULL_HANDLE;
  bool owned_ = false;
};

struct Device {
  // Members are destroyed in reverse order: pipelines, pool, allocator, device, instance, log.
  std::shared_ptr<MessageLog> log;
  Instance instance;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  LogicalDevice device;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;
  DeviceInfo info;
  VkPhysicalDeviceLimits limits{};
  std::uint32_t timestamp_valid_bits = 0;
  std::unique_ptr<Allocator> allocator;
  DeviceObject<VkCommandPool> command_pool;
  std::unique_ptr<Pipelines> pipelines; // created on first use (pipelines.h)

  Device(std::shared_ptr<MessageLog> message_log, Instance vk_instance);
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;
  ~Device(); // waits for an owned device to be idle before anything is destroyed

  VkDevice vk() const { return device.get(); }
  Pipelines& compute_pipelines();
};

// Throws RuntimeError (no_device, ...).
std::shared_ptr<Device> create_device(const ContextOptions& options);
std::shared_ptr<Device> borrow_device(const HostVulkan& host, const ContextOptions& options);

} // namespace probebake::runtime::detail
