// Move-only owners of Vulkan device-level objects: DeviceObject<VkBuffer>(device, buffer, vkDestroyBuffer)
// destroys the handle once, in its destructor or reset(). Instance-level objects (instance, messenger,
// device) have their own owners in instance.h and device.h.
#pragma once

#include <utility>

#include <vulkan/vulkan_core.h>

namespace probebake::runtime::detail {

// A zeroed Vulkan info struct with its sType set.
template <class T>
T vk_struct(VkStructureType type) {
  T value{};
  value.sType = type;
  return value;
}

template <class Handle>
class DeviceObject {
public:
  using Destroy = void(VKAPI_PTR*)(VkDevice, Handle, const VkAllocationCallbacks*);

  DeviceObject() = default;
  DeviceObject(VkDevice device, Handle handle, Destroy destroy) : device_(device), handle_(handle), destroy_(destroy) {}
  DeviceObject(const DeviceObject&) = delete;
  DeviceObject& operator=(const DeviceObject&) = delete;
  DeviceObject(DeviceObject&& other) noexcept { swap(other); }
  DeviceObject& operator=(DeviceObject&& other) noexcept {
    DeviceObject moved(std::move(other));
    swap(moved);
    return *this;
  }
  ~DeviceObject() { reset(); }

  void reset() {
    if (handle_ != VK_NULL_HANDLE) destroy_(device_, handle_, nullptr);
    handle_ = VK_NULL_HANDLE;
  }
  // Gives up ownership without destroying.
  Handle release() { return std::exchange(handle_, VK_NULL_HANDLE); }
  Handle get() const { return handle_; }
  explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }

private:
  void swap(DeviceObject& other) noexcept {
    std::swap(device_, other.device_);
    std::swap(handle_, other.handle_);
    std::swap(destroy_, other.destroy_);
  }

  VkDevice device_ = VK_NULL_HANDLE;
  Handle handle_ = VK_NULL_HANDLE;
  Destroy destroy_ = nullptr;
};

} // namespace probebake::runtime::detail
