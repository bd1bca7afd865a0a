#include "core/allocator.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <utility>

#include "core/error.h"
#include "core/handles.h"

namespace probebake::runtime::detail {
namespace {

struct MemoryFlags {
  VkMemoryPropertyFlags required;
  VkMemoryPropertyFlags preferred;
  VkMemoryPropertyFlags avoided;
};

MemoryFlags flags_for(MemoryUse use) {
  constexpr VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  switch (use) {
  case MemoryUse::device: return {0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0};
  case MemoryUse::upload: return {host, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT}; // keep scarce BAR memory free
  case MemoryUse::readback: return {host, VK_MEMORY_PROPERTY_HOST_CACHED_BIT, 0};
  }
  return {0, 0, 0};
}

} // namespace

// ---- Buffer ----------------------------------------------------------------------------------------------
Buffer::Buffer(Buffer&& other) noexcept { take(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    take(other);
  }
  return *this;
}

Buffer::~Buffer() { release(); }

void Buffer::take(Buffer& other) noexcept {
  allocator_ = std::exchange(other.allocator_, nullptr);
  buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
  memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
  size_ = std::exchange(other.size_, 0);
  mapped_ = std::exchange(other.mapped_, nullptr);
}

void Buffer::release() {
  if (allocator_ && buffer_ != VK_NULL_HANDLE) allocator_->destroy(buffer_, memory_);
  allocator_ = nullptr;
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  size_ = 0;
  mapped_ = nullptr;
}

// ---- Allocator -------------------------------------------------------------------------------------------
Allocator::Allocator(VkPhysicalDevice physical_device, VkDevice device) : device_(device) {
  vkGetPhysicalDeviceMemoryProperties(physical_device, &memory_);
  auto maintenance3 =
      vk_struct<VkPhysicalDeviceMaintenance3Properties>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES);
  auto properties = vk_struct<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
  properties.pNext = &maintenance3;
  vkGetPhysicalDeviceProperties2(physical_device, &properties);
  max_allocation_size_ = maintenance3.maxMemoryAllocationSize;
}

Allocator::~Allocator() {
  if (live_.empty()) return;
  std::fprintf(stderr, "probebake runtime: %zu buffer(s) leaked at shutdown:\n%s", live_.size(), live_report().c_str());
}

std::uint32_t Allocator::memory_type(std::uint32_t allowed_types, MemoryUse use) const {
  const MemoryFlags flags = flags_for(use);
  int best = -1;
  int best_score = 0;
  for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    const VkMemoryPropertyFlags has = memory_.memoryTypes[i].propertyFlags;
    if (!(allowed_types & (1u << i)) || (has & flags.required) != flags.required) continue;
    const int score = 2 * std::popcount(has & flags.preferred) - std::popcount(has & flags.avoided);
    if (best < 0 || score > best_score) {
      best = static_cast<int>(i);
      best_score = score;
    }
  }
  if (best < 0) fail(StatusCode::unsupported, "no memory type fits a runtime buffer");
  return static_cast<std::uint32_t>(best);
}

Buffer Allocator::create_buffer(VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use, const std::string& name) {
  if (size == 0) fail(StatusCode::internal, "create_buffer: " + name + " has size 0");
  if (max_allocation_size_ != 0 && size > max_allocation_size_)
    fail(StatusCode::unsupported, name + ": " + std::to_string(size) + " bytes exceed maxMemoryAllocationSize (" +
                                      std::to_string(max_allocation_size_) + ")");
  auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer raw_buffer = VK_NULL_HANDLE;
  check_vk(vkCreateBuffer(device_, &info, nullptr, &raw_buffer), "vkCreateBuffer");
  DeviceObject<VkBuffer> buffer(device_, raw_buffer, vkDestroyBuffer);

  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device_, buffer.get(), &requirements);
  auto allocate = vk_struct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex = memory_type(requirements.memoryTypeBits, use);
  VkDeviceMemory raw_memory = VK_NULL_HANDLE;
  check_vk(vkAllocateMemory(device_, &allocate, nullptr, &raw_memory), ("vkAllocateMemory for " + name).c_str());
  DeviceObject<VkDeviceMemory> memory(device_, raw_memory, vkFreeMemory);
  check_vk(vkBindBufferMemory(device_, buffer.get(), memory.get(), 0), "vkBindBufferMemory");
  void* mapped = nullptr;
  if (use != MemoryUse::device)
    check_vk(vkMapMemory(device_, memory.get(), 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");

  live_.emplace(buffer.get(), Live{name, requirements.size});
  live_bytes_ += requirements.size;
  peak_bytes_ = std::max(peak_bytes_, live_bytes_);
  ++allocations_;
  Buffer result; // nothing below throws: ownership moves from the guards to `result`
  result.allocator_ = this;
  result.buffer_ = buffer.release();
  result.memory_ = memory.release();
  result.size_ = size;
  result.mapped_ = mapped;
  return result;
}

void Allocator::destroy(VkBuffer buffer, VkDeviceMemory memory) {
  vkDestroyBuffer(device_, buffer, nullptr);
  vkFreeMemory(device_, memory, nullptr); // unmaps implicitly
  auto it = live_.find(buffer);
  if (it == live_.end()) return;
  live_bytes_ -= it->second.size;
  live_.erase(it);
}

MemoryStats Allocator::stats() const { return {live_.size(), live_bytes_, peak_bytes_, allocations_}; }

std::string Allocator::live_report() const {
  std::string report;
  for (const auto& [buffer, live] : live_) report += "  " + live.name + " (" + std::to_string(live.size) + " bytes)\n";
  return report;
}

} // namespace probebake::runtime::detail
