// The Vulkan instance: created by the runtime (Vulkan 1.2, optionally with VK_LAYER_KHRONOS_validation,
// synchronization validation and a debug-utils messenger that counts messages) or borrowed from the host.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

// Validation messages: counted, the first kKeep kept as text, each passed to the host's callback.
// Written from whatever thread makes a Vulkan call, so it is synchronised.
class MessageLog {
public:
  static constexpr std::size_t kKeep = 64;
  explicit MessageLog(std::function<void(const ValidationMessage&)> callback) : callback_(std::move(callback)) {}
  void add(const ValidationMessage& message);
  std::uint64_t count() const { return count_.load(); }
  std::vector<std::string> kept() const;

private:
  std::function<void(const ValidationMessage&)> callback_;
  std::atomic<std::uint64_t> count_{0};
  mutable std::mutex mutex_;
  std::vector<std::string> kept_;
};

class Instance {
public:
  // Throws RuntimeError(no_device) without a Vulkan 1.2 loader or, with validation, without the layer.
  static Instance create(bool validation, std::shared_ptr<MessageLog> log);
  static Instance borrow(VkInstance instance);

  Instance(Instance&& other) noexcept;
  Instance& operator=(Instance&& other) noexcept;
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;
  ~Instance();

  VkInstance get() const { return instance_; }
  bool validation() const { return messenger_ != VK_NULL_HANDLE; }

private:
  Instance() = default;
  void release();

  VkInstance instance_ = VK_NULL_HANDLE;
  bool owned_ = false;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  std::shared_ptr<MessageLog> log_; // the messenger's user data: lives as long as the messenger
};

} // namespace probebake::runtime::detail
