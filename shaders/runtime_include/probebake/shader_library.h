// The runtime's compute shaders as SPIR-V words, compiled at build time from shaders/*.comp
// (shaders/CMakeLists.txt) and embedded in the library.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace probebake::shaders {

// SPIR-V of the shader built from shaders/<name>.comp; an empty span when there is none of that name.
std::span<const std::uint32_t> spirv(std::string_view name);

} // namespace probebake::shaders
