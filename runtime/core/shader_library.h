// The runtime's compute kernels as SPIR-V words, compiled at build time from the pass table's kernel rows
// (runtime/<folder>/<name>.comp, runtime/CMakeLists.txt) and embedded in the library.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace probebake::shaders {

// SPIR-V of the kernel `name` (its row in passes.def); an empty span when there is none of that name.
std::span<const std::uint32_t> spirv(std::string_view name);

} // namespace probebake::shaders
