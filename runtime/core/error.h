// Errors inside the runtime: RuntimeError carries the public StatusCode; every public function catches
// and converts it (and formats' probebake::Error, std::bad_alloc, ...) with status_from_current_exception.
#pragma once

#include <stdexcept>
#include <string>

#include <vulkan/vulkan_core.h>

#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

class RuntimeError : public std::runtime_error {
public:
  RuntimeError(StatusCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  StatusCode code() const { return code_; }

private:
  StatusCode code_;
};

[[noreturn]] void fail(StatusCode code, const std::string& message);

const char* vk_result_name(VkResult result);
// Throws RuntimeError (out_of_memory, no_device or vulkan_error) naming `what` when result < 0.
void check_vk(VkResult result, const char* what);

// Call only inside a catch block: the Status for the exception being handled.
Status status_from_current_exception();

// Runs `body` and converts any exception into a Status (body returns Status or a Result<T>).
template <class Body>
auto guarded(Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (...) {
    return status_from_current_exception();
  }
}

} // namespace probebake::runtime::detail
