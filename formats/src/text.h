// String building for one-line error and violation messages (formats/ does not depend on fmt).
#pragma once

#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>

namespace probebake::formats::detail {

template <typename... Args>
std::string concat(const Args&... args) {
  std::ostringstream stream;
  (stream << ... << args);
  return stream.str();
}

inline std::string hex64(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(value));
  return text;
}

} // namespace probebake::formats::detail
