#include "core/error.h"

#include <new>

#include "probebake/formats/error.h"

namespace probebake::runtime {

const char* to_string(StatusCode code) {
  switch (code) {
  case StatusCode::ok: return "ok";
  case StatusCode::invalid_argument: return "invalid_argument";
  case StatusCode::file_error: return "file_error";
  case StatusCode::invalid_volume: return "invalid_volume";
  case StatusCode::no_device: return "no_device";
  case StatusCode::unsupported: return "unsupported";
  case StatusCode::out_of_memory: return "out_of_memory";
  case StatusCode::vulkan_error: return "vulkan_error";
  case StatusCode::too_slow: return "too_slow";
  case StatusCode::internal: return "internal";
  }
  return "unknown";
}

namespace detail {

void fail(StatusCode code, const std::string& message) { throw RuntimeError(code, message); }

const char* vk_result_name(VkResult result) {
  switch (result) {
  case VK_SUCCESS: return "VK_SUCCESS";
  case VK_NOT_READY: return "VK_NOT_READY";
  case VK_TIMEOUT: return "VK_TIMEOUT";
  case VK_INCOMPLETE: return "VK_INCOMPLETE";
  case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
  case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
  case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
  case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
  case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
  case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
  case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
  case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
  case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
  case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
  case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
  case VK_ERROR_FRAGMENTED_POOL: return "VK_ERROR_FRAGMENTED_POOL";
  case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
  default: return "VkResult error";
  }
}

void check_vk(VkResult result, const char* what) {
  if (result >= 0) return;
  const std::string message =
      std::string(what) + ": " + vk_result_name(result) + " (" + std::to_string(static_cast<int>(result)) + ")";
  switch (result) {
  case VK_ERROR_OUT_OF_HOST_MEMORY:
  case VK_ERROR_OUT_OF_DEVICE_MEMORY:
  case VK_ERROR_OUT_OF_POOL_MEMORY: fail(StatusCode::out_of_memory, message);
  case VK_ERROR_INCOMPATIBLE_DRIVER:
  case VK_ERROR_LAYER_NOT_PRESENT:
  case VK_ERROR_INITIALIZATION_FAILED: fail(StatusCode::no_device, message);
  default: fail(StatusCode::vulkan_error, message);
  }
}

Status status_from_current_exception() {
  try {
    throw;
  } catch (const RuntimeError& e) {
    return {e.code(), e.what()};
  } catch (const Error& e) {
    // formats' errors: bad input is a file problem, the rest are bugs on one side or the other.
    const StatusCode code = e.kind() == ErrorKind::input   ? StatusCode::file_error
                            : e.kind() == ErrorKind::usage ? StatusCode::invalid_argument
                                                           : StatusCode::internal;
    return {code, e.what()};
  } catch (const std::bad_alloc&) {
    return {StatusCode::out_of_memory, "out of host memory"};
  } catch (const std::exception& e) {
    return {StatusCode::internal, e.what()};
  } catch (...) {
    return {StatusCode::internal, "unknown exception"};
  }
}

} // namespace detail
} // namespace probebake::runtime
