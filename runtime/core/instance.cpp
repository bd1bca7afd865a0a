#include "core/instance.h"

#include <cstring>
#include <utility>

#include "core/error.h"
#include "core/handles.h"

namespace probebake::runtime::detail {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

ValidationMessage::Severity severity_of(VkDebugUtilsMessageSeverityFlagBitsEXT severity) {
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) return ValidationMessage::Severity::error;
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return ValidationMessage::Severity::warning;
  return ValidationMessage::Severity::info;
}

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                          VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                          const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  ValidationMessage message;
  message.severity = severity_of(severity);
  message.id = data && data->pMessageIdName ? data->pMessageIdName : "";
  message.text = data && data->pMessage ? data->pMessage : "";
  static_cast<MessageLog*>(user)->add(message);
  return VK_FALSE;
}

VkDebugUtilsMessengerCreateInfoEXT messenger_info(MessageLog* log) {
  auto info = vk_struct<VkDebugUtilsMessengerCreateInfoEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
  info.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  info.pfnUserCallback = on_message;
  info.pUserData = log;
  return info;
}

bool has_layer(const char* name) {
  std::uint32_t count = 0;
  check_vk(vkEnumerateInstanceLayerProperties(&count, nullptr), "vkEnumerateInstanceLayerProperties");
  std::vector<VkLayerProperties> layers(count);
  check_vk(vkEnumerateInstanceLayerProperties(&count, layers.data()), "vkEnumerateInstanceLayerProperties");
  for (const VkLayerProperties& layer : layers)
    if (std::strcmp(layer.layerName, name) == 0) return true;
  return false;
}

void require_loader_1_2() {
  std::uint32_t version = VK_API_VERSION_1_0;
  check_vk(vkEnumerateInstanceVersion(&version), "vkEnumerateInstanceVersion");
  if (version < VK_API_VERSION_1_2)
    fail(StatusCode::no_device, "the Vulkan loader supports Vulkan " + std::to_string(VK_API_VERSION_MAJOR(version)) +
                                    "." + std::to_string(VK_API_VERSION_MINOR(version)) + ", the runtime needs 1.2");
}

} // namespace

void MessageLog::add(const ValidationMessage& message) {
  count_.fetch_add(1);
  {
    std::lock_guard lock(mutex_);
    if (kept_.size() < kKeep) kept_.push_back(message.id + ": " + message.text);
  }
  if (callback_) callback_(message);
}

std::vector<std::string> MessageLog::kept() const {
  std::lock_guard lock(mutex_);
  return kept_;
}

Instance Instance::create(bool validation, std::shared_ptr<MessageLog> log) {
  require_loader_1_2();
  if (validation && !has_layer(kValidationLayer))
    fail(StatusCode::no_device, std::string(kValidationLayer) + " is not installed (Debian: vulkan-validationlayers)");

  auto app = vk_struct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "probebake runtime";
  app.pEngineName = "probebake";
  app.apiVersion = VK_API_VERSION_1_2;

  const char* layers[] = {kValidationLayer};
  const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
  const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  auto features = vk_struct<VkValidationFeaturesEXT>(VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT);
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  VkDebugUtilsMessengerCreateInfoEXT messenger = messenger_info(log.get());
  messenger.pNext = &features; // also reports messages of vkCreateInstance / vkDestroyInstance themselves

  auto info = vk_struct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  info.pApplicationInfo = &app;
  if (validation) {
    info.pNext = &messenger;
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = layers;
    info.enabledExtensionCount = 2;
    info.ppEnabledExtensionNames = extensions;
  }
  Instance instance;
  check_vk(vkCreateInstance(&info, nullptr, &instance.instance_), "vkCreateInstance");
  instance.owned_ = true;
  if (!validation) return instance;

  instance.log_ = std::move(log);
  auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance.instance_, "vkCreateDebugUtilsMessengerEXT"));
  if (!create) fail(StatusCode::no_device, "vkCreateDebugUtilsMessengerEXT is not available");
  VkDebugUtilsMessengerCreateInfoEXT persistent = messenger_info(instance.log_.get());
  check_vk(create(instance.instance_, &persistent, nullptr, &instance.messenger_), "vkCreateDebugUtilsMessengerEXT");
  return instance;
}

Instance Instance::borrow(VkInstance handle) {
  Instance instance;
  instance.instance_ = handle;
  return instance;
}

Instance::Instance(Instance&& other) noexcept
    : instance_(std::exchange(other.instance_, VK_NULL_HANDLE)),
      owned_(std::exchange(other.owned_, false)),
      messenger_(std::exchange(other.messenger_, VK_NULL_HANDLE)),
      log_(std::move(other.log_)) {}

Instance& Instance::operator=(Instance&& other) noexcept {
  if (this != &other) {
    release();
    instance_ = std::exchange(other.instance_, VK_NULL_HANDLE);
    owned_ = std::exchange(other.owned_, false);
    messenger_ = std::exchange(other.messenger_, VK_NULL_HANDLE);
    log_ = std::move(other.log_);
  }
  return *this;
}

Instance::~Instance() { release(); }

void Instance::release() {
  if (messenger_ != VK_NULL_HANDLE) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (owned_ && instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
  instance_ = VK_NULL_HANDLE;
  owned_ = false;
}

} // namespace probebake::runtime::detail
