// The .probes format version, defined here and nowhere else. Major: incompatible layout changes (a reader
// refuses other majors). Minor: compatible additions (new optional sections).
#pragma once

#include <cstdint>

namespace probebake::formats {
inline constexpr std::uint16_t kFormatVersionMajor = 1;
inline constexpr std::uint16_t kFormatVersionMinor = 0;
} // namespace probebake::formats
