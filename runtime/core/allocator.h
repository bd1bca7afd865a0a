// A small device-memory allocator: one VkDeviceMemory per buffer (the runtime makes about a dozen buffers
// per volume; docs/RUNTIME.md compares this with VMA). create_buffer creates, allocates, binds and maps in
// one call and leaves nothing half-made on failure; live buffers are tracked by name and reported as leaks
// when the allocator is destroyed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include <vulkan/vulkan_core.h>

#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

enum class MemoryUse {
  device,   // GPU-only storage (device-local when there is such memory)
  upload,   // host-visible, coherent, mapped: staging for host -> device copies
  readback, // host-visible, coherent, mapped, cached when possible: staging for device -> host copies
};

class Allocator;

class Buffer {
public:
  Buffer() = default;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  ~Buffer();

  VkBuffer get() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  // Host pointer of upload and readback buffers, nullptr for device buffers.
  void* mapped() const { return mapped_; }
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

private:
  friend class Allocator;
  void release();
  void take(Buffer& other) noexcept;

  Allocator* allocator_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

class Allocator {
public:
  Allocator(VkPhysicalDevice physical_device, VkDevice device);
  Allocator(const Allocator&) = delete;
  Allocator& operator=(const Allocator&) = delete;
  // Reports live buffers (leaks) on stderr.
  ~Allocator();

  // size > 0. Throws RuntimeError: unsupported (over maxMemoryAllocationSize, no suitable memory type),
  // out_of_memory, vulkan_error. `name` identifies the buffer in leak reports.
  Buffer create_buffer(VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use, const std::string& name);

  MemoryStats stats() const;
  // Names and sizes of live buffers, e.g. "probes (1440 bytes)", one per line.
  std::string live_report() const;

private:
  friend class Buffer;
  std::uint32_t memory_type(std::uint32_t allowed_types, MemoryUse use) const;
  void destroy(VkBuffer buffer, VkDeviceMemory memory);

  VkDevice device_;
  VkPhysicalDeviceMemoryProperties memory_{};
  VkDeviceSize max_allocation_size_ = 0;
  struct Live {
    std::string name;
    VkDeviceSize size = 0;
  };
  std::map<VkBuffer, Live> live_;
  std::uint64_t live_bytes_ = 0;
  std::uint64_t peak_bytes_ = 0;
  std::size_t allocations_ = 0;
};

} // namespace probebake::runtime::detail
